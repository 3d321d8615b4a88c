#include "core/sim/depth_noise.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace icgm::sim {

double QuantizeDepth(const DepthNoiseOptions& o, double z_m, double disparity_noise_px) {
  if (!(o.disparity_focal_baseline_px_m > 0.0) || !(z_m > 0.0)) return z_m;
  const double fb = o.disparity_focal_baseline_px_m;
  const double step = o.disparity_step_px;
  const double d = std::max(step, step * std::round((fb / z_m + disparity_noise_px) / step));
  return fb / d;
}

double DepthNoiseSigma(const DepthNoiseOptions& o, double z_m) {
  const double dz = z_m - o.sigma_offset_m;
  return o.sigma_base_m + o.sigma_quadratic_per_m * dz * dz;
}

void ApplyDepthNoise(const DepthNoiseOptions& o, const cv::Mat& ideal, Rng& rng, cv::Mat* depth) {
  CV_Assert(ideal.type() == CV_32FC1);
  const float nan = std::numeric_limits<float>::quiet_NaN();
  // Bulk random numbers from OpenCV's generator, seeded from the simulation's engine.
  cv::RNG cv_rng(rng());
  cv::Mat gauss(ideal.size(), CV_32FC1), coin(ideal.size(), CV_32FC1);
  cv_rng.fill(gauss, cv::RNG::NORMAL, 0.0, 1.0);
  cv_rng.fill(coin, cv::RNG::UNIFORM, 0.0, 1.0);
  // Drawn only when quantizing, so scenarios without it keep their random sequence.
  const bool quantize = o.disparity_focal_baseline_px_m > 0.0;
  cv::Mat disparity_noise;
  if (quantize) {
    disparity_noise.create(ideal.size(), CV_32FC1);
    cv_rng.fill(disparity_noise, cv::RNG::NORMAL, 0.0, 1.0);
  }
  depth->create(ideal.size(), CV_32FC1);
  const float jump = static_cast<float>(o.edge_jump_fraction);
  const float dropout = static_cast<float>(o.dropout_probability);
  const float edge_p = static_cast<float>(o.edge_hole_probability);
  for (int v = 0; v < ideal.rows; ++v) {
    const float* z = ideal.ptr<float>(v);
    const float* up = ideal.ptr<float>(std::max(v - 1, 0));
    const float* down = ideal.ptr<float>(std::min(v + 1, ideal.rows - 1));
    const float* g = gauss.ptr<float>(v);
    const float* c = coin.ptr<float>(v);
    float* out = depth->ptr<float>(v);
    for (int u = 0; u < ideal.cols; ++u) {
      const float zi = z[u];
      if (!(zi >= o.min_range_m && zi <= o.max_range_m)) {
        out[u] = nan;
        continue;
      }
      // Depth edge: a 4-neighbour differs by more than jump * z.
      const float left = z[std::max(u - 1, 0)], right = z[std::min(u + 1, ideal.cols - 1)];
      const float tol = jump * zi;
      const bool edge = std::abs(left - zi) > tol || std::abs(right - zi) > tol ||
                        std::abs(up[u] - zi) > tol || std::abs(down[u] - zi) > tol;
      if (c[u] < dropout || (edge && c[u] < dropout + edge_p)) {
        out[u] = nan;
        continue;
      }
      const float zq =
          quantize ? static_cast<float>(QuantizeDepth(
                         o, zi, o.disparity_sigma_px * disparity_noise.at<float>(v, u)))
                   : zi;
      out[u] = zq + static_cast<float>(DepthNoiseSigma(o, zi)) * g[u];
    }
  }
}

}  // namespace icgm::sim
