#include "core/dataset/depth_image.h"

#include <cmath>
#include <limits>
#include <vector>

#include "core/dataset/depth_traits.h"

namespace icgm {

namespace {

template <typename T>
void Convert(const cv::Mat& raw, double depth_scale, double min_m, double max_m, cv::Mat* out_m) {
  out_m->create(raw.rows, raw.cols, CV_32FC1);
  cv::Mat& out = *out_m;
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
}

// 16-bit depth: the metres of all 65536 raw values, computed once with Convert's rule and
// looked up per pixel (a division per pixel cost about as much as the rest of a frame's input
// handling). Kept per thread while the scale and range stay the same.
const std::vector<float>& Uint16Metres(double depth_scale, double min_m, double max_m) {
  struct Table {
    double scale = 0.0, min_m = 0.0, max_m = 0.0;
    std::vector<float> metres;
  };
  thread_local Table table;
  if (table.metres.empty() || table.scale != depth_scale || table.min_m != min_m ||
      table.max_m != max_m) {
    const cv::Mat all = [] {
      cv::Mat raw(1, 65536, CV_16UC1);
      for (int v = 0; v < 65536; ++v) raw.at<uint16_t>(0, v) = static_cast<uint16_t>(v);
      return raw;
    }();
    cv::Mat metres;
    Convert<uint16_t>(all, depth_scale, min_m, max_m, &metres);
    table = {depth_scale, min_m, max_m, std::vector<float>(metres.ptr<float>(0),
                                                           metres.ptr<float>(0) + 65536)};
  }
  return table.metres;
}

void ConvertUint16(const cv::Mat& raw, double depth_scale, double min_m, double max_m,
                   cv::Mat* out) {
  const std::vector<float>& metres = Uint16Metres(depth_scale, min_m, max_m);
  out->create(raw.rows, raw.cols, CV_32FC1);
  for (int r = 0; r < raw.rows; ++r) {
    const uint16_t* in_row = raw.ptr<uint16_t>(r);
    float* out_row = out->ptr<float>(r);
    for (int c = 0; c < raw.cols; ++c) out_row[c] = metres[in_row[c]];
  }
}

}  // namespace

cv::Mat ToMetricDepth(const cv::Mat& raw, double depth_scale, double min_m, double max_m) {
  cv::Mat out;
  ToMetricDepth(raw, depth_scale, &out, min_m, max_m);
  return out;
}

bool ToMetricDepth(const cv::Mat& raw, double depth_scale, cv::Mat* depth_m, double min_m,
                   double max_m) {
  const bool ok = !raw.empty() && min_m <= max_m &&
                  (raw.type() == CV_32FC1 ||
                   (raw.type() == CV_16UC1 && depth_scale > 0.0 && std::isfinite(depth_scale)));
  if (!ok) {
    depth_m->release();
    return false;
  }
  if (raw.type() == CV_16UC1) {
    ConvertUint16(raw, depth_scale, min_m, max_m, depth_m);
  } else {
    Convert<float>(raw, depth_scale, min_m, max_m, depth_m);
  }
  return true;
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
