// Robust rigid alignment of 3-D correspondences: RANSAC (Fischler & Bolles, CACM 24(6), 1981)
// around Horn's closed-form absolute orientation (Horn, JOSA A 4(4), 1987; HornAlign).
//
// Estimates T with dst_i ~ T * src_i. Each hypothesis is fitted to a minimal sample of 3
// correspondences (drawn with a seedable std::mt19937_64, so a seed fixes the result); a
// correspondence is an inlier when |T src_i - dst_i| <= inlier_threshold_m. The number of
// iterations adapts to the best inlier ratio w seen so far, N = log(1 - p) / log(1 - w^3) for
// confidence p (Fischler-Bolles sec. IV.A), capped at max_iterations. The best hypothesis is then
// refined on all its inliers: re-fit with Horn, re-classify, repeated refine_rounds times or
// until the inlier set stops changing.
// With local_optimization (LO-RANSAC, Chum, Matas & Kittler, DAGM 2003), every sample that beats
// the best so far is refitted the same way before it competes, so the refitted consistent sets,
// not the minimal samples' own noise, decide which wins.
#pragma once

#include <cstdint>
#include <vector>

#include <Eigen/Core>

#include "core/common/camera.h"
#include "core/common/pose.h"
#include "core/common/status.h"

namespace icgm {

struct RansacOptions {
  double inlier_threshold_m = 0.03;
  int max_iterations = 300;
  // Probability that at least one all-inlier sample is drawn (adaptive iteration count).
  double confidence = 0.995;
  int refine_rounds = 3;
  int min_inliers = 10;
  uint64_t rng_seed = 7;
  // Sample points closer than this to each other are degenerate for a minimal sample.
  double min_sample_spread_m = 0.01;
  // Each new best sample refitted on its inliers (Horn, re-classified, at most refine_rounds
  // times or until the set stops changing) before it is compared: the draws then matter less.
  bool local_optimization = false;
};

struct RansacResult {
  Status status = Status::Ok();
  Pose3 transform = Pose3::Identity();  // dst ~ transform * src
  std::vector<int> inliers;             // indices into src/dst, increasing
  double rmse_m = 0.0;                  // over the final inliers
  int iterations = 0;                   // hypotheses drawn
};

// Image-space inlier test (projective RANSAC) in place of the 3-D distance: with dst ~ T src,
// correspondence i is an inlier when T src_i reprojects within threshold_px * sigma_px[i] of
// dst_px[i], T^-1 dst_i within it of src_px[i], and the two depths agree within
// depth_abs_m + depth_rel_per_m * z^2. Far points, whose depth noise hides a wrong motion in
// 3-D, are judged by where they appear; walkers moving a few centimetres fail it.
struct ReprojectionInlierTest {
  CameraIntrinsics intrinsics;
  std::vector<Eigen::Vector2d> src_px, dst_px;
  std::vector<double> sigma_px;  // per correspondence, empty = 1
  double threshold_px = 3.0;
  double depth_abs_m = 0.03;
  double depth_rel_per_m = 0.015;
};

// Fails with a reason for size mismatch, fewer than 3 correspondences, no non-degenerate sample
// or fewer than min_inliers final inliers ("too few inliers: 6 < 10").
// With `test`, inliers are judged by it instead of inlier_threshold_m.
RansacResult RansacHorn(const std::vector<Eigen::Vector3d>& src,
                        const std::vector<Eigen::Vector3d>& dst, const RansacOptions& options,
                        const ReprojectionInlierTest* test = nullptr);

// Number of RANSAC iterations needed to draw an all-inlier sample of `sample_size` with
// probability `confidence` when a fraction `inlier_ratio` of the data are inliers.
int AdaptiveIterations(double inlier_ratio, int sample_size, double confidence, int cap);

}  // namespace icgm
