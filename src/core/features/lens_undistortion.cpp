#include "core/features/lens_undistortion.h"

#include <limits>

#include <opencv2/calib3d.hpp>
#include <opencv2/imgproc.hpp>

namespace icgm {

LensUndistortion::LensUndistortion(const CameraIntrinsics& c)
    : k_(c.fx_px, 0, c.cx_px, 0, c.fy_px, c.cy_px, 0, 0, 1),
      d_(c.distortion_k1, c.distortion_k2, c.distortion_p1, c.distortion_p2, c.distortion_k3) {
  if (!c.HasDistortion()) return;
  cv::initUndistortRectifyMap(k_, d_, cv::Matx33d::eye(), k_, cv::Size(c.width_px, c.height_px),
                              CV_32FC1, map_x_, map_y_);
}

bool LensUndistortion::Fits(const cv::Mat& image) const {
  return active() && !image.empty() && image.size() == map_x_.size();
}

cv::Mat LensUndistortion::Colour(const cv::Mat& raw) const {
  if (!Fits(raw)) return raw;
  cv::Mat ideal;  // a fresh buffer: remap into a header sharing `raw` would overwrite the caller's
  cv::remap(raw, ideal, map_x_, map_y_, cv::INTER_LINEAR);
  return ideal;
}

cv::Mat LensUndistortion::Depth(const cv::Mat& raw_m) const {
  if (!Fits(raw_m) || raw_m.type() != CV_32FC1) return raw_m;
  cv::Mat ideal;
  cv::remap(raw_m, ideal, map_x_, map_y_, cv::INTER_NEAREST, cv::BORDER_CONSTANT,
            cv::Scalar(std::numeric_limits<float>::quiet_NaN()));
  return ideal;
}

void LensUndistortion::MoveKeypoints(std::vector<cv::KeyPoint>* keypoints) const {
  if (!active() || keypoints->empty()) return;
  std::vector<cv::Point2f> raw, ideal;
  raw.reserve(keypoints->size());
  for (const cv::KeyPoint& k : *keypoints) raw.push_back(k.pt);
  cv::undistortPoints(raw, ideal, k_, d_, cv::noArray(), k_);
  for (size_t i = 0; i < ideal.size(); ++i) (*keypoints)[i].pt = ideal[i];
}

}  // namespace icgm
