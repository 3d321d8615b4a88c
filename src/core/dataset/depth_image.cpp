#include "core/dataset/depth_image.h"

#include <cmath>
#include <limits>

#include "core/dataset/depth_traits.h"

namespace icgm {

namespace {

template <typename T>
cv::Mat Convert(const cv::Mat& raw, double depth_scale, double min_m, double max_m) {
  cv::Mat out(raw.rows, raw.cols, CV_32FC1);
  const float nan = std::numeric_limits<float>::quiet_NaN();
  for (int r = 0; r < raw.rows; ++r) {
    const T* in_row = raw.ptr<T>(r);
    float* out_row = out.ptr<float>(r);
    for (int c = 0; c < raw.cols; ++c) {
      const T v = in_row[c];
      if (!DepthTraits<T>::Valid(v)) {
        out_row[c] = nan;
        continue;
      }
      const float d = DepthTraits<T>::ToMetres(v, depth_scale);
      out_row[c] = (d >= min_m && d <= max_m) ? d : nan;
    }
  }
  return out;
}

}  // namespace

cv::Mat ToMetricDepth(const cv::Mat& raw, double depth_scale, double min_m, double max_m) {
  if (raw.empty() || !(min_m <= max_m)) return cv::Mat();
  switch (raw.type()) {
    case CV_16UC1:
      if (!(depth_scale > 0.0) || !std::isfinite(depth_scale)) return cv::Mat();
      return Convert<uint16_t>(raw, depth_scale, min_m, max_m);
    case CV_32FC1:
      return Convert<float>(raw, depth_scale, min_m, max_m);
    default:
      return cv::Mat();
  }
}

int CountValidDepth(const cv::Mat& depth_m) {
  if (depth_m.empty() || depth_m.type() != CV_32FC1) return 0;
  int n = 0;
  for (int r = 0; r < depth_m.rows; ++r) {
    const float* row = depth_m.ptr<float>(r);
    for (int c = 0; c < depth_m.cols; ++c) n += std::isfinite(row[c]) ? 1 : 0;
  }
  return n;
}

}  // namespace icgm
