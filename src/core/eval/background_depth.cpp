#include "core/eval/background_depth.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include <opencv2/imgproc.hpp>

namespace icgm {
namespace {

// Source depth moved into the target, nearest per pixel (0: not seen).
cv::Mat Warp(const cv::Mat& depth, const Pose3& target_from_source,
             const CameraIntrinsics& intrinsics, int stride_px) {
  const int w = intrinsics.width_px, h = intrinsics.height_px;
  const float inf = std::numeric_limits<float>::infinity();
  cv::Mat nearest(h, w, CV_32FC1, cv::Scalar(inf));
  for (int v = 0; v < depth.rows; v += stride_px) {
    const float* z = depth.ptr<float>(v);
    for (int u = 0; u < depth.cols; u += stride_px) {
      if (!(z[u] > 0.0f)) continue;
      const Eigen::Vector3d p = target_from_source * intrinsics.BackProject(u, v, z[u]);
      if (p.z() <= 0.1) continue;
      const Eigen::Vector2d uv = intrinsics.Project(p);
      // Splat over the stride so that the sampled source covers the target.
      const int x0 = static_cast<int>(std::floor(uv.x()));
      const int y0 = static_cast<int>(std::floor(uv.y()));
      for (int y = std::max(y0, 0); y < std::min(y0 + stride_px, h); ++y) {
        float* row = nearest.ptr<float>(y);
        for (int x = std::max(x0, 0); x < std::min(x0 + stride_px, w); ++x) {
          row[x] = std::min(row[x], static_cast<float>(p.z()));
        }
      }
    }
  }
  nearest.setTo(0.0f, nearest == inf);
  return nearest;
}

}  // namespace

cv::Mat BackgroundDepth(const std::vector<cv::Mat>& source_depths_m,
                        const std::vector<Pose3>& T_world_source, const Pose3& T_world_target,
                        const CameraIntrinsics& intrinsics, int stride_px, int spread_px,
                        int min_sources) {
  const int w = intrinsics.width_px, h = intrinsics.height_px;
  const Pose3 target_from_world = T_world_target.inverse();
  std::vector<cv::Mat> warped;
  const size_t n = std::min(source_depths_m.size(), T_world_source.size());
  for (size_t k = 0; k < n; ++k) {
    if (source_depths_m[k].type() != CV_32FC1) continue;
    warped.push_back(
        Warp(source_depths_m[k], target_from_world * T_world_source[k], intrinsics, stride_px));
  }
  const float inf = std::numeric_limits<float>::infinity();
  cv::Mat median(h, w, CV_32FC1, cv::Scalar(inf));
  std::vector<float> values;
  for (int v = 0; v < h; ++v) {
    float* out = median.ptr<float>(v);
    for (int u = 0; u < w; ++u) {
      values.clear();
      for (const cv::Mat& m : warped) {
        const float z = m.at<float>(v, u);
        if (z > 0.0f) values.push_back(z);
      }
      if (static_cast<int>(values.size()) < min_sources) continue;
      const size_t k = values.size() / 2;
      std::nth_element(values.begin(), values.begin() + k, values.end());
      out[u] = values[k];
    }
  }
  if (spread_px > 0) {
    cv::erode(
        median, median,
        cv::getStructuringElement(cv::MORPH_RECT, cv::Size(2 * spread_px + 1, 2 * spread_px + 1)));
  }
  median.setTo(0.0f, median == inf);
  return median;
}

cv::Mat ForegroundMask(const cv::Mat& depth_m, const cv::Mat& background_m, double min_m,
                       double fraction) {
  cv::Mat mask(depth_m.size(), CV_8UC1, cv::Scalar(0));
  if (depth_m.type() != CV_32FC1 || background_m.type() != CV_32FC1 ||
      background_m.size() != depth_m.size()) {
    return mask;
  }
  for (int v = 0; v < depth_m.rows; ++v) {
    const float* z = depth_m.ptr<float>(v);
    const float* b = background_m.ptr<float>(v);
    uint8_t* m = mask.ptr<uint8_t>(v);
    for (int u = 0; u < depth_m.cols; ++u) {
      if (!(z[u] > 0.0f) || !(b[u] > 0.0f)) continue;
      if (b[u] - z[u] > std::max(min_m, fraction * b[u])) m[u] = 255;
    }
  }
  return mask;
}

}  // namespace icgm
