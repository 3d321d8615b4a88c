#include "core/registration/depth_warp.h"

#include <algorithm>
#include <cassert>
#include <cmath>
#include <limits>
#include <vector>

namespace icgm {

cv::Mat WarpDepthImage(const cv::Mat& depth_m, const CameraIntrinsics& k,
                       const Pose3& target_from_source, int iterations) {
  return WarpDepthImageByRow(depth_m, k,
                             std::vector<Pose3>(std::max(depth_m.rows, 0), target_from_source),
                             iterations);
}

cv::Mat WarpDepthImageByRow(const cv::Mat& depth_m, const CameraIntrinsics& k,
                            const std::vector<Pose3>& target_from_source_row, int iterations) {
  assert(depth_m.type() == CV_32FC1);
  assert(static_cast<int>(target_from_source_row.size()) == depth_m.rows);
  constexpr float kNaN = std::numeric_limits<float>::quiet_NaN();
  const int cols = depth_m.cols, rows = depth_m.rows;
  cv::Mat out(depth_m.size(), CV_32FC1, cv::Scalar(kNaN));
  // Per source row: source_from_target (rotation a, translation t) and the depth row of
  // target_from_source (z_target(q) = b q + bt); scalar floats in the pixel loop, which runs on
  // every frame.
  struct RowMotion {
    float a[9], t[3], b[3], bt;
  };
  std::vector<RowMotion> motion(rows);
  for (int v = 0; v < rows; ++v) {
    const Pose3& ts = target_from_source_row[v];
    const Pose3 st = ts.inverse();
    RowMotion& m = motion[v];
    for (int i = 0; i < 3; ++i) {
      for (int j = 0; j < 3; ++j) m.a[3 * i + j] = static_cast<float>(st.linear()(i, j));
      m.t[i] = static_cast<float>(st.translation()(i));
      m.b[i] = static_cast<float>(ts.linear()(2, i));
    }
    m.bt = static_cast<float>(ts.translation().z());
  }
  // Normalized ray coordinates per column and row: ray(u, v) = (ray_x[u], ray_y[v], 1).
  std::vector<float> ray_x(cols), ray_y(rows);
  for (int u = 0; u < cols; ++u) ray_x[u] = (u - k.cx_px) / k.fx_px;
  for (int v = 0; v < rows; ++v) ray_y[v] = (v - k.cy_px) / k.fy_px;
  const float fx = k.fx_px, fy = k.fy_px, cx = k.cx_px + 0.5, cy = k.cy_px + 0.5;
  for (int v = 0; v < rows; ++v) {
    const float* src_row = depth_m.ptr<float>(v);
    float* row = out.ptr<float>(v);
    const float yv = ray_y[v];
    for (int u = 0; u < cols; ++u) {
      // Ray of the target pixel; its depth is unknown, start from the source's at the same
      // pixel, and the motion of the same row.
      float z_target = src_row[u];
      if (!(z_target > 0.0f) || !std::isfinite(z_target)) continue;
      const float xu = ray_x[u];
      const RowMotion* m = &motion[v];
      bool ok = true;
      for (int it = 0; it < iterations; ++it) {
        const float* a = m->a;
        const float rx = a[0] * xu + a[1] * yv + a[2];
        const float ry = a[3] * xu + a[4] * yv + a[5];
        const float rz = a[6] * xu + a[7] * yv + a[8];
        const float pz = z_target * rz + m->t[2];
        if (!(pz > 0.0f)) {
          ok = false;
          break;
        }
        // Nearest source pixel; truncation rounds here since negative positions are rejected
        // first (std::floor is a library call on baseline x86-64).
        const float inv_z = 1.0f / pz;
        const float us_f = fx * (z_target * rx + m->t[0]) * inv_z + cx;
        const float vs_f = fy * (z_target * ry + m->t[1]) * inv_z + cy;
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
        // The source's point on the ray through (us, vs), captured with row vs's motion, seen
        // from the target: its depth is where the target ray meets it.
        m = &motion[vs];
        z_target = z_source * (m->b[0] * ray_x[us] + m->b[1] * ray_y[vs] + m->b[2]) + m->bt;
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
