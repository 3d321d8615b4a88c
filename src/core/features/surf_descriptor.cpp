#include "core/features/surf_descriptor.h"

#include <algorithm>
#include <array>
#include <cmath>

#include "core/features/integral_box.h"

namespace icgm {

double SurfOrientation(const cv::Mat& integral, cv::Point2f position_px, double scale_px) {
  const int half = std::max(1, static_cast<int>(std::lround(2.0 * scale_px)));
  // The Gaussian (sigma 2s) at sample (i s, j s) is exp(-(i^2 + j^2) / 8) whatever s is.
  static const std::array<double, 37> kWeight = [] {
    std::array<double, 37> w{};
    for (int d2 = 0; d2 < 37; ++d2) w[d2] = std::exp(-d2 / 8.0);
    return w;
  }();
  // Weighted responses summed in 5-degree bins of their angle; the pi/3 window then slides
  // over 12 consecutive bins (the window's sum is exact up to the bin edges, its direction is
  // the angle of the summed vector, not a bin centre).
  constexpr int kBins = 72;
  constexpr int kWindowBins = 12;
  std::array<double, kBins> bin_x{}, bin_y{};
  bool any = false;
  for (int j = -6; j <= 6; ++j) {
    for (int i = -6; i <= 6; ++i) {
      if (i * i + j * j >= 36) continue;
      const int x = static_cast<int>(std::lround(position_px.x + i * scale_px));
      const int y = static_cast<int>(std::lround(position_px.y + j * scale_px));
      float rx = 0.0f, ry = 0.0f;
      HaarXY(integral, x, y, half, &rx, &ry);
      if (rx == 0.0f && ry == 0.0f) continue;
      any = true;
      const double w = kWeight[i * i + j * j];
      const int bin = std::min(kBins - 1, static_cast<int>(cv::fastAtan2(ry, rx) / 5.0f));
      bin_x[bin] += w * rx;
      bin_y[bin] += w * ry;
    }
  }
  if (!any) return 0.0;
  double sum_x = 0.0, sum_y = 0.0;
  for (int k = 0; k < kWindowBins; ++k) {
    sum_x += bin_x[k];
    sum_y += bin_y[k];
  }
  double best_norm2 = -1.0;
  double best_angle = 0.0;
  for (int start = 0; start < kBins; ++start) {
    const double norm2 = sum_x * sum_x + sum_y * sum_y;
    if (norm2 > best_norm2) {
      best_norm2 = norm2;
      best_angle = std::atan2(sum_y, sum_x);
    }
    const int leaving = start;
    const int entering = (start + kWindowBins) % kBins;
    sum_x += bin_x[entering] - bin_x[leaving];
    sum_y += bin_y[entering] - bin_y[leaving];
  }
  return best_angle;
}

void SurfDescribe(const cv::Mat& integral, cv::Point2f position_px, double scale_px,
                  double orientation_rad, float* out) {
  const double co = std::cos(orientation_rad);
  const double si = std::sin(orientation_rad);
  const int half = std::max(1, static_cast<int>(std::lround(scale_px)));
  const double sigma = 3.3 * scale_px;
  const double inv_two_sigma2 = 1.0 / (2.0 * sigma * sigma);
  // Gaussian weights depend only on the sample's place in the 20 x 20 grid.
  std::array<double, 20> g1{};
  for (int k = 0; k < 20; ++k) {
    const double u = (k - 9.5) * scale_px;
    g1[k] = std::exp(-u * u * inv_two_sigma2);
  }
  double norm2 = 0.0;
  for (int sv = 0; sv < 4; ++sv) {
    for (int su = 0; su < 4; ++su) {
      double sdx = 0.0, sadx = 0.0, sdy = 0.0, sady = 0.0;
      for (int kv = 0; kv < 5; ++kv) {
        const int gv = sv * 5 + kv;
        const double v = (gv - 9.5) * scale_px;
        for (int ku = 0; ku < 5; ++ku) {
          const int gu = su * 5 + ku;
          const double u = (gu - 9.5) * scale_px;
          const int x = static_cast<int>(std::lround(position_px.x + co * u - si * v));
          const int y = static_cast<int>(std::lround(position_px.y + si * u + co * v));
          const double w = g1[gu] * g1[gv];
          float rx = 0.0f, ry = 0.0f;
          HaarXY(integral, x, y, half, &rx, &ry);
          // Responses in the keypoint's frame (u along the orientation).
          const double dx = w * (co * rx + si * ry);
          const double dy = w * (-si * rx + co * ry);
          sdx += dx;
          sadx += std::abs(dx);
          sdy += dy;
          sady += std::abs(dy);
        }
      }
      float* o = out + 4 * (sv * 4 + su);
      o[0] = static_cast<float>(sdx);
      o[1] = static_cast<float>(sadx);
      o[2] = static_cast<float>(sdy);
      o[3] = static_cast<float>(sady);
      norm2 += sdx * sdx + sadx * sadx + sdy * sdy + sady * sady;
    }
  }
  const float inv = norm2 > 0.0 ? static_cast<float>(1.0 / std::sqrt(norm2)) : 0.0f;
  for (int k = 0; k < kSurfDescriptorSize; ++k) out[k] *= inv;
}

}  // namespace icgm
