#include "core/sim/motion_blur.h"

#include <algorithm>
#include <cmath>

#include <Eigen/Core>

namespace icgm::sim {
namespace {

// Bilinear sample of a CV_8UC3 image at (x, y), clamped to the border; adds into sum[3].
inline void AddBilinear(const cv::Mat& img, float x, float y, float* sum) {
  x = std::clamp(x, 0.0f, static_cast<float>(img.cols - 1));
  y = std::clamp(y, 0.0f, static_cast<float>(img.rows - 1));
  const int x0 = static_cast<int>(x), y0 = static_cast<int>(y);
  // On the last row or column the far neighbour has weight 0: reuse the near one.
  const int dx = x0 + 1 < img.cols ? 3 : 0;
  const size_t dy = y0 + 1 < img.rows ? img.step[0] : 0;
  const float fx = x - x0, fy = y - y0;
  const uint8_t* a = img.ptr<uint8_t>(y0) + 3 * x0;
  const uint8_t* c = a + dy;
  const float wa = (1 - fx) * (1 - fy), wb = fx * (1 - fy), wc = (1 - fx) * fy, wd = fx * fy;
  for (int k = 0; k < 3; ++k) sum[k] += wa * a[k] + wb * a[dx + k] + wc * c[k] + wd * c[dx + k];
}

}  // namespace

void ApplyMotionBlur(const CameraIntrinsics& K, const cv::Mat& depth_m, const Pose3& T_mid_start,
                     const Pose3& T_mid_end, cv::Mat* bgr, int max_samples) {
  CV_Assert(bgr->type() == CV_8UC3 && depth_m.type() == CV_32FC1 && depth_m.size() == bgr->size());
  const cv::Mat src = bgr->clone();
  // A point X in the middle frame lies at T_mid_start^-1 * X in the start frame.
  const Eigen::Matrix3f R_s = T_mid_start.linear().transpose().cast<float>();
  const Eigen::Vector3f t_s = -(R_s * T_mid_start.translation().cast<float>());
  const Eigen::Matrix3f R_e = T_mid_end.linear().transpose().cast<float>();
  const Eigen::Vector3f t_e = -(R_e * T_mid_end.translation().cast<float>());
  const float fx = K.fx_px, fy = K.fy_px, cx = K.cx_px, cy = K.cy_px;
  for (int v = 0; v < src.rows; ++v) {
    const float* z_row = depth_m.ptr<float>(v);
    uint8_t* out = bgr->ptr<uint8_t>(v);
    const float yn = (v - cy) / fy;
    for (int u = 0; u < src.cols; ++u) {
      const float z = z_row[u];
      if (!(z > 0.0f)) continue;
      const Eigen::Vector3f X((u - cx) / fx * z, yn * z, z);
      const Eigen::Vector3f Xs = R_s * X + t_s, Xe = R_e * X + t_e;
      if (Xs.z() <= 1e-3f || Xe.z() <= 1e-3f) continue;
      const float us = fx * Xs.x() / Xs.z() + cx, vs = fy * Xs.y() / Xs.z() + cy;
      const float ue = fx * Xe.x() / Xe.z() + cx, ve = fy * Xe.y() / Xe.z() + cy;
      const float len = std::sqrt((u - us) * (u - us) + (v - vs) * (v - vs)) +
                        std::sqrt((ue - u) * (ue - u) + (ve - v) * (ve - v));
      if (len < 0.5f) continue;
      const int n = std::clamp(static_cast<int>(std::ceil(len)) + 1, 2, max_samples);
      float sum[3] = {0.0f, 0.0f, 0.0f};
      for (int k = 0; k < n; ++k) {
        // s in [-1, 1]: start -> middle for s < 0, middle -> end for s > 0.
        const float s = -1.0f + 2.0f * k / (n - 1);
        const float x = s < 0.0f ? u + (u - us) * s : u + (ue - u) * s;
        const float y = s < 0.0f ? v + (v - vs) * s : v + (ve - v) * s;
        AddBilinear(src, x, y, sum);
      }
      for (int k = 0; k < 3; ++k) {
        out[3 * u + k] = static_cast<uint8_t>(std::clamp(sum[k] / n + 0.5f, 0.0f, 255.0f));
      }
    }
  }
}

}  // namespace icgm::sim
