#include "core/registration/depth_warp.h"

#include <cassert>
#include <cmath>
#include <limits>
#include <vector>

namespace icgm {

cv::Mat WarpDepthImage(const cv::Mat& depth_m, const CameraIntrinsics& k,
                       const Pose3& target_from_source, int iterations) {
  assert(depth_m.type() == CV_32FC1);
  constexpr float kNaN = std::numeric_limits<float>::quiet_NaN();
  const int cols = depth_m.cols, rows = depth_m.rows;
  cv::Mat out(depth_m.size(), CV_32FC1, cv::Scalar(kNaN));
  const Pose3 source_from_target = target_from_source.inverse();
  const Eigen::Matrix3d r_st = source_from_target.linear();
  const Eigen::Vector3d t_st = source_from_target.translation();
  // Only the depth row of target_from_source is needed: z_target(q) = r_ts.row(2) q + t_ts.z.
  const Eigen::RowVector3d r_ts_z = target_from_source.linear().row(2);
  const double t_ts_z = target_from_source.translation().z();
  // Normalized ray coordinates per column and row: ray(u, v) = (ray_x[u], ray_y[v], 1).
  std::vector<float> ray_x(cols), ray_y(rows);
  for (int u = 0; u < cols; ++u) ray_x[u] = (u - k.cx_px) / k.fx_px;
  for (int v = 0; v < rows; ++v) ray_y[v] = (v - k.cy_px) / k.fy_px;
  // Scalar float arithmetic in the pixel loop (this runs on every frame).
  const float a00 = r_st(0, 0), a01 = r_st(0, 1), a02 = r_st(0, 2);
  const float a10 = r_st(1, 0), a11 = r_st(1, 1), a12 = r_st(1, 2);
  const float a20 = r_st(2, 0), a21 = r_st(2, 1), a22 = r_st(2, 2);
  const float tx = t_st.x(), ty = t_st.y(), tz = t_st.z();
  const float b0 = r_ts_z(0), b1 = r_ts_z(1), b2 = r_ts_z(2), bt = t_ts_z;
  const float fx = k.fx_px, fy = k.fy_px, cx = k.cx_px + 0.5, cy = k.cy_px + 0.5;
  for (int v = 0; v < rows; ++v) {
    const float* src_row = depth_m.ptr<float>(v);
    float* row = out.ptr<float>(v);
    // r_st * ray(u, v) = ray_x[u] * r_st.col(0) + (ray_y[v] * r_st.col(1) + r_st.col(2)).
    const float yv = ray_y[v];
    const float c0 = a01 * yv + a02, c1 = a11 * yv + a12, c2 = a21 * yv + a22;
    for (int u = 0; u < cols; ++u) {
      // Ray of the target pixel; its depth is unknown, start from the source's at the same pixel.
      float z_target = src_row[u];
      if (!(z_target > 0.0f) || !std::isfinite(z_target)) continue;
      const float xu = ray_x[u];
      const float rx = a00 * xu + c0, ry = a10 * xu + c1, rz = a20 * xu + c2;
      bool ok = true;
      for (int it = 0; it < iterations; ++it) {
        const float pz = z_target * rz + tz;
        if (!(pz > 0.0f)) {
          ok = false;
          break;
        }
        // Nearest source pixel; truncation rounds here since negative positions are rejected
        // first (std::floor is a library call on baseline x86-64).
        const float inv_z = 1.0f / pz;
        const float us_f = fx * (z_target * rx + tx) * inv_z + cx;
        const float vs_f = fy * (z_target * ry + ty) * inv_z + cy;
        if (!(us_f >= 0.0f && vs_f >= 0.0f && us_f < cols && vs_f < rows)) {
          ok = false;
          break;
        }
        const int us = static_cast<int>(us_f);
        const int vs = static_cast<int>(vs_f);
        const float z_source = depth_m.ptr<float>(vs)[us];
        if (!(z_source > 0.0f) || !std::isfinite(z_source)) {
          ok = false;
          break;
        }
        // The source's point on the ray through (us, vs), seen from the target: its depth is
        // where the target ray meets it.
        z_target = z_source * (b0 * ray_x[us] + b1 * ray_y[vs] + b2) + bt;
        if (!(z_target > 0.0f)) {
          ok = false;
          break;
        }
      }
      if (ok) row[u] = z_target;
    }
  }
  return out;
}

}  // namespace icgm
