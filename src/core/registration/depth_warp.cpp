#include "core/registration/depth_warp.h"

#include <cassert>
#include <cmath>
#include <limits>

namespace icgm {

cv::Mat WarpDepthImage(const cv::Mat& depth_m, const CameraIntrinsics& k,
                       const Pose3& target_from_source, int iterations) {
  assert(depth_m.type() == CV_32FC1);
  constexpr float kNaN = std::numeric_limits<float>::quiet_NaN();
  cv::Mat out(depth_m.size(), CV_32FC1, cv::Scalar(kNaN));
  const Pose3 source_from_target = target_from_source.inverse();
  const Eigen::Matrix3d r_st = source_from_target.linear();
  const Eigen::Vector3d t_st = source_from_target.translation();
  const Eigen::Matrix3d r_ts = target_from_source.linear();
  const Eigen::Vector3d t_ts = target_from_source.translation();
  const auto depth_at = [&](int u, int v) -> double {
    if (u < 0 || v < 0 || u >= depth_m.cols || v >= depth_m.rows) return 0.0;
    const float z = depth_m.at<float>(v, u);
    return std::isfinite(z) && z > 0.0f ? z : 0.0;
  };
  for (int v = 0; v < depth_m.rows; ++v) {
    float* row = out.ptr<float>(v);
    for (int u = 0; u < depth_m.cols; ++u) {
      // Ray of the target pixel; its depth is unknown, start from the source's at the same pixel.
      double z_target = depth_at(u, v);
      if (z_target <= 0.0) continue;
      const Eigen::Vector3d ray = k.BackProject(u, v, 1.0);
      bool ok = true;
      for (int it = 0; it < iterations && ok; ++it) {
        const Eigen::Vector3d p_source = r_st * (ray * z_target) + t_st;
        if (p_source.z() <= 0.0) {
          ok = false;
          break;
        }
        const Eigen::Vector2d px = k.Project(p_source);
        const int us = static_cast<int>(std::lround(px.x()));
        const int vs = static_cast<int>(std::lround(px.y()));
        const double z_source = depth_at(us, vs);
        if (z_source <= 0.0) {
          ok = false;
          break;
        }
        // The source's point on the ray through (us, vs), seen from the target.
        const Eigen::Vector3d q = r_ts * k.BackProject(us, vs, z_source) + t_ts;
        // Depth along the target ray: where the target ray meets that point's depth.
        z_target = q.z();
        if (!(z_target > 0.0)) ok = false;
      }
      if (ok) row[u] = static_cast<float>(z_target);
    }
  }
  return out;
}

}  // namespace icgm
