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

namespace {

// Per distinct pose of the source rows: source_from_target (rotation a, translation t) and the
// depth row of target_from_source (z_target(q) = b q + bt), as scalar floats.
struct RowMotion {
  float a[9], t[3], b[3], bt;
};

// The pixel loop. kOneMotion: every row has motion[0] (a plain rigid warp), which lets the
// compiler keep the motion in registers; the general case follows each source row's motion.
template <bool kOneMotion>
void WarpPixels(const cv::Mat& depth_m, const CameraIntrinsics& k,
                const std::vector<RowMotion>& motion, const std::vector<int>& motion_of_row,
                int iterations, cv::Mat* out) {
  const int cols = depth_m.cols, rows = depth_m.rows;
  // Normalized ray coordinates per column and row: ray(u, v) = (ray_x[u], ray_y[v], 1).
  std::vector<float> ray_x(cols), ray_y(rows);
  for (int u = 0; u < cols; ++u) ray_x[u] = (u - k.cx_px) / k.fx_px;
  for (int v = 0; v < rows; ++v) ray_y[v] = (v - k.cy_px) / k.fy_px;
  const float fx = k.fx_px, fy = k.fy_px, cx = k.cx_px + 0.5, cy = k.cy_px + 0.5;
  const RowMotion first = motion[0];
  for (int v = 0; v < rows; ++v) {
    const float* src_row = depth_m.ptr<float>(v);
    float* row = out->ptr<float>(v);
    const float yv = ray_y[v];
    // With the target row's own motion, a * ray(u, v) = ray_x[u] * a.col(0) + c (per row).
    const int own = kOneMotion ? 0 : motion_of_row[v];
    const float* a_own = kOneMotion ? first.a : motion[own].a;
    const float c0 = a_own[1] * yv + a_own[2], c1 = a_own[4] * yv + a_own[5],
                c2 = a_own[7] * yv + a_own[8];
    for (int u = 0; u < cols; ++u) {
      // Ray of the target pixel; its depth is unknown, start from the source's at the same
      // pixel, and the motion of the same row.
      float z_target = src_row[u];
      if (!(z_target > 0.0f) || !std::isfinite(z_target)) continue;
      const float xu = ray_x[u];
      int mi = own;
      bool ok = true;
      for (int it = 0; it < iterations; ++it) {
        const RowMotion& m = kOneMotion ? first : motion[mi];
        const float* a = m.a;
        float rx, ry, rz;
        if (kOneMotion || mi == own) {
          rx = a[0] * xu + c0;
          ry = a[3] * xu + c1;
          rz = a[6] * xu + c2;
        } else {
          rx = a[0] * xu + a[1] * yv + a[2];
          ry = a[3] * xu + a[4] * yv + a[5];
          rz = a[6] * xu + a[7] * yv + a[8];
        }
        const float pz = z_target * rz + m.t[2];
        if (!(pz > 0.0f)) {
          ok = false;
          break;
        }
        // Nearest source pixel; truncation rounds here since negative positions are rejected
        // first (std::floor is a library call on baseline x86-64).
        const float inv_z = 1.0f / pz;
        const float us_f = fx * (z_target * rx + m.t[0]) * inv_z + cx;
        const float vs_f = fy * (z_target * ry + m.t[1]) * inv_z + cy;
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
        if (!kOneMotion) mi = motion_of_row[vs];
        const RowMotion& ms = kOneMotion ? first : motion[mi];
        z_target = z_source * (ms.b[0] * ray_x[us] + ms.b[1] * ray_y[vs] + ms.b[2]) + ms.bt;
        if (!(z_target > 0.0f)) {
          ok = false;
          break;
        }
      }
      if (ok) row[u] = z_target;
    }
  }
}

}  // namespace

cv::Mat WarpDepthImageByRow(const cv::Mat& depth_m, const CameraIntrinsics& k,
                            const std::vector<Pose3>& target_from_source_row, int iterations) {
  assert(depth_m.type() == CV_32FC1);
  assert(static_cast<int>(target_from_source_row.size()) == depth_m.rows);
  const int rows = depth_m.rows;
  cv::Mat out(depth_m.size(), CV_32FC1, cv::Scalar(std::numeric_limits<float>::quiet_NaN()));
  if (rows == 0) return out;
  // One entry per run of rows sharing a pose.
  std::vector<RowMotion> motion;
  std::vector<int> motion_of_row(rows);
  for (int v = 0; v < rows; ++v) {
    const Pose3& ts = target_from_source_row[v];
    if (v > 0 && ts.matrix() == target_from_source_row[v - 1].matrix()) {
      motion_of_row[v] = motion_of_row[v - 1];
      continue;
    }
    motion_of_row[v] = static_cast<int>(motion.size());
    const Pose3 st = ts.inverse();
    RowMotion& m = motion.emplace_back();
    for (int i = 0; i < 3; ++i) {
      for (int j = 0; j < 3; ++j) m.a[3 * i + j] = static_cast<float>(st.linear()(i, j));
      m.t[i] = static_cast<float>(st.translation()(i));
      m.b[i] = static_cast<float>(ts.linear()(2, i));
    }
    m.bt = static_cast<float>(ts.translation().z());
  }
  if (motion.size() == 1) {
    WarpPixels<true>(depth_m, k, motion, motion_of_row, iterations, &out);
  } else {
    WarpPixels<false>(depth_m, k, motion, motion_of_row, iterations, &out);
  }
  return out;
}

}  // namespace icgm
