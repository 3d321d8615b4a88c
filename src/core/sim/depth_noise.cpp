#include "core/sim/depth_noise.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include <opencv2/imgproc.hpp>

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
  ApplyDepthHoles(o, ideal, cv_rng, depth);
}

void ApplyDepthHoles(const DepthNoiseOptions& o, const cv::Mat& ideal, cv::RNG& cv_rng,
                     cv::Mat* depth) {
  const float nan = std::numeric_limits<float>::quiet_NaN();
  if (o.shadow_band_px > 0) {
    // The nearest depth within the band; a pixel deeper than it by the edge fraction is shadowed.
    cv::Mat finite = ideal.clone();
    cv::patchNaNs(finite, 1e6);
    cv::Mat nearest;
    const int k = 2 * o.shadow_band_px + 1;
    cv::erode(finite, nearest, cv::getStructuringElement(cv::MORPH_ELLIPSE, cv::Size(k, k)));
    const float factor = 1.f + static_cast<float>(o.edge_jump_fraction);
    for (int v = 0; v < ideal.rows; ++v) {
      const float* z = finite.ptr<float>(v);
      const float* n = nearest.ptr<float>(v);
      float* out = depth->ptr<float>(v);
      for (int u = 0; u < ideal.cols; ++u) {
        if (z[u] > factor * n[u]) out[u] = nan;
      }
    }
  }
  if (o.border_band_px > 0) {
    const int b = o.border_band_px;
    for (int v = 0; v < depth->rows; ++v) {
      float* out = depth->ptr<float>(v);
      const bool row_in_band = v < b || v >= depth->rows - b;
      for (int u = 0; u < depth->cols; ++u) {
        if (row_in_band || u < b || u >= depth->cols - b) out[u] = nan;
      }
    }
  }
  const bool far = o.far_hole_start_m > 0.0 && o.far_hole_probability > 0.0;
  if (o.hole_probability <= 0.0 && !far) return;
  // Drawn only when on, so scenarios without holes keep their random sequence.
  const int block = o.hole_block_px;
  cv::Mat coin((ideal.rows + block - 1) / block + 1, (ideal.cols + block - 1) / block + 1,
               CV_32FC1);
  cv_rng.fill(coin, cv::RNG::UNIFORM, 0.0, 1.0);
  const int du = static_cast<int>(cv_rng.uniform(0, block));
  const int dv = static_cast<int>(cv_rng.uniform(0, block));
  const double far_span = std::max(1e-6, o.max_range_m - o.far_hole_start_m);
  for (int v = 0; v < ideal.rows; ++v) {
    const float* z = ideal.ptr<float>(v);
    const float* c = coin.ptr<float>((v + dv) / block);
    float* out = depth->ptr<float>(v);
    for (int u = 0; u < ideal.cols; ++u) {
      double p = o.hole_probability;
      if (far && z[u] > o.far_hole_start_m) {
        p += o.far_hole_probability * std::min(1.0, (z[u] - o.far_hole_start_m) / far_span);
      }
      if (c[(u + du) / block] < p) out[u] = nan;
    }
  }
}

}  // namespace icgm::sim
