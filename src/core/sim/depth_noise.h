// Kinect-like depth sensor effects applied to an ideal depth image: axial Gaussian noise with
// sigma(z) = sigma_base + sigma_quadratic * (z - sigma_offset)^2 (Khoshelham & Elberink 2012
// style), invalid (NaN) outside [min_range, max_range], random dropout, and holes along depth
// discontinuities where the structured-light pattern breaks up; optionally (options'
// disparity_focal_baseline_px_m > 0) the disparity quantization of a structured-light sensor,
// and (options' shadow_band_px, hole_probability, far_hole_*) an Xtion's larger holes.
#pragma once

#include <opencv2/core.hpp>

#include "core/sim/procedural_textures.h"
#include "core/sim/sim_options.h"

namespace icgm::sim {

// z_m as a structured-light sensor reports it: the disparity f*b/z plus disparity_noise_px,
// rounded to the options' disparity step. Returns z_m unchanged when quantization is off.
double QuantizeDepth(const DepthNoiseOptions& options, double z_m, double disparity_noise_px);

// Standard deviation of the Gaussian depth noise at depth z_m.
double DepthNoiseSigma(const DepthNoiseOptions& options, double z_m);

// `ideal_depth_m`: CV_32FC1 camera z; `depth_m` receives CV_32FC1 with NaN for invalid pixels.
// The options' Xtion-like missing depth (shadow band, solid and far holes) set to NaN in
// `depth_m`, from the ideal depth; draws from `cv_rng` only when holes are on. Called by
// ApplyDepthNoise.
void ApplyDepthHoles(const DepthNoiseOptions& options, const cv::Mat& ideal_depth_m,
                     cv::RNG& cv_rng, cv::Mat* depth_m);

void ApplyDepthNoise(const DepthNoiseOptions& options, const cv::Mat& ideal_depth_m, Rng& rng,
                     cv::Mat* depth_m);

}  // namespace icgm::sim
