// Test scene for RGB-D registration: the inside of an axis-aligned box room rendered as a metric
// depth image from any camera pose, so two views under a known motion give exact ground truth.
#pragma once

#include <cmath>
#include <limits>

#include <opencv2/core.hpp>

#include "core/common/camera.h"
#include "core/common/pose.h"

namespace icgm::test {

inline CameraIntrinsics TumLikeCamera() {
  CameraIntrinsics k;
  k.fx_px = 517.3;
  k.fy_px = 516.5;
  k.cx_px = 318.6;
  k.cy_px = 255.3;
  k.depth_scale = 5000.0;
  return k;
}

// Room [-2, 2] x [-1.5, 1.5] x [-1, 4] (world frame = reference camera frame). Returns the depth
// (camera z) seen by a camera at T_world_camera, CV_32FC1 metres.
inline cv::Mat RenderRoomDepth(const Pose3& t_world_camera, const CameraIntrinsics& k) {
  const double lo[3] = {-2.0, -1.5, -1.0};
  const double hi[3] = {2.0, 1.5, 4.0};
  cv::Mat depth(k.height_px, k.width_px, CV_32FC1);
  const Eigen::Matrix3d r = t_world_camera.linear();
  const Eigen::Vector3d o = t_world_camera.translation();
  for (int v = 0; v < k.height_px; ++v) {
    for (int u = 0; u < k.width_px; ++u) {
      const Eigen::Vector3d ray_c((u - k.cx_px) / k.fx_px, (v - k.cy_px) / k.fy_px, 1.0);
      const Eigen::Vector3d ray_w = r * ray_c;
      double t_hit = std::numeric_limits<double>::infinity();
      for (int a = 0; a < 3; ++a) {
        if (std::abs(ray_w[a]) < 1e-12) continue;
        const double wall = ray_w[a] > 0 ? hi[a] : lo[a];
        const double t = (wall - o[a]) / ray_w[a];
        if (t > 0 && t < t_hit) t_hit = t;
      }
      // ray_c has z = 1, so the ray parameter is the camera depth.
      depth.at<float>(v, u) = static_cast<float>(t_hit);
    }
  }
  return depth;
}

}  // namespace icgm::test
