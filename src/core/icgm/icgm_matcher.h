// Incremental Center of Gravity Matching (ICGM), thesis ch. 4.1.2, Algorithm 1.
//
// Input: putative matches p_k <-> p'_k between images I_0 and I_1 (pixel coordinates).
// A random seed pair (i, j) with RoD(p_i - p_j, p'_i - p'_j) <= Thr starts the consistent set
// and its centres of gravity CG_0, CG_1 (eq. 4.15). Every other match k is tested once, in input
// order, with the centre-of-gravity vectors CGV_0 = CG_0 - p_k, CGV_1 = CG_1 - p'_k (eq. 4.16)
// and the ratio of difference (eq. 4.19)
//     RoD = |CGV_0 - CGV_1| / (|CGV_0| + |CGV_1|);
// matches with RoD <= Thr are kept and update the centres incrementally,
//     CG <- (SCG * CG + p_k) / (SCG + 1),  SCG <- SCG + 1.
// Unlike the printed pseudo-code, the seed pair itself is part of the result.
//
// Extensions beyond the thesis; seed_pairs = 1, refine = false, auto_threshold = false is
// exactly Algorithm 1:
//  - seed_pairs > 1 (robust seeding): run the pass from several random seeds and keep the
//    largest consistent set, so one seed on a moving object cannot decide the result.
//  - refine (order independence): after the pass, re-test every match against the current
//    centres (CG = mean of the kept set) until the kept set stops changing.
//  - auto_threshold: Thr chosen from the data (the thesis leaves this to future work, ch. 5.1):
//    the knee of the kept-count curve N(Thr) of thesis Fig. 5.1. N is evaluated on a geometric
//    grid of Thr in [auto_threshold_min, auto_threshold_max] (3 seeds, refinement); the first
//    grid value after which N grows by < 3 % over the next two steps is the knee, where the
//    static structure is complete and moving objects do not pass yet; plateaus with less than
//    half the largest count are skipped (a rigid mover can be the only consistent set when Thr
//    is below the static RoD, e.g. under strong in-plane rotation). Thr = knee *
//    auto_threshold_scale, clamped to the bounds.
//  - motion prior (motion_prior, and RunIcgm given `predicted_b`): for a camera whose motion is
//    predicted (the odometry's wheels), predicted_b[k] is where p_k would appear in image b if
//    it were static. ICGM then runs on predicted_b[k] <-> p'_k instead of p_k <-> p'_k, with
//    Thr = motion_prior_threshold: the predicted camera motion is taken out, so the static
//    structure barely moves (up to the prediction error) and everything moving on its own
//    stands out, whatever the perspective change of the baseline. Matches without a prediction
//    are never kept. Seed pairs are drawn among the matches within motion_prior_tolerance_px of
//    their prediction, and the consistent set holding most such matches wins (ties: the larger
//    set), so a walker filling the view cannot win by size. Without a prior, or with fewer than
//    two predicted matches, the plain rules above apply.
//
// Cost: O(n) per seed pass and per refinement sweep; the only allocations are the output and
// one scratch buffer of n bytes per call (with a motion prior, also the list of agreeing
// matches).
#pragma once

#include <cstdint>
#include <vector>

#include <Eigen/Core>

#include "core/common/status.h"

namespace icgm {

class OptionReader;

struct IcgmOptions {
  // RoD threshold Thr (eq. 4.19, 4.20). The thesis uses 0.075-0.082 (ch. 5.1-5.3). RoD lies in
  // [0, 1] (triangle inequality), so Thr = 1 keeps every usable match: the thesis' Thr -> inf.
  double threshold = 0.08;
  // Choose Thr from the data (rule above); `threshold` is then ignored.
  bool auto_threshold = false;
  // Bounds for the automatic threshold.
  double auto_threshold_min = 0.02;
  double auto_threshold_max = 0.2;
  // Automatic Thr = auto_threshold_scale * knee of the kept-count curve (margin).
  double auto_threshold_scale = 1.5;
  // Number of independent seed pairs; the largest consistent set wins. Thesis: 1. Default 5:
  // on rendered scenes with four moving patches a single seed lands on a patch in ~15 % of the
  // runs and returns the patch; 5 seeds never did (icgm_matcher_test), at 5x an O(n) pass.
  int seed_pairs = 5;
  // Random pair draws per seed before giving up (no consistent pair exists).
  int max_seed_attempts = 200;
  // Re-test all matches against the final centres until a fixed point (order independence).
  bool refine = false;
  int max_refine_iterations = 10;
  // Seed of the std::mt19937_64 used to draw seed pairs; same seed, same result.
  uint64_t rng_seed = 42;
  // Use predicted positions when the caller has them (rule above); false: Algorithm 1 rules.
  bool motion_prior = false;
  // Thr for predicted <-> observed positions (threshold and auto_threshold are then unused).
  double motion_prior_threshold = 0.02;
  // A match within this distance of its predicted position agrees with the prior.
  double motion_prior_tolerance_px = 8.0;
  // With the prior: RoD's denominator is at least this many pixels,
  //     RoD = |CGV_0 - CGV_1| / max(|CGV_0| + |CGV_1|, floor),
  // so a match near the centres of gravity, whose short vectors make RoD large on pixel noise
  // alone, is judged by an absolute tolerance of Thr * floor pixels instead (0: eq. 4.19).
  double motion_prior_rod_floor_px = 0.0;
};

// Fills `options` from an `icgm:` section; throws LoadError on bad values.
void ReadOptions(const OptionReader& reader, IcgmOptions* options);

struct IcgmResult {
  // Per input match, 1 = kept (robust), 0 = rejected.
  std::vector<uint8_t> kept;
  size_t num_kept = 0;
  // Thr actually used (differs from options.threshold with auto_threshold).
  double threshold_used = 0.0;
  // Final centres of gravity of the kept set in image a and b (zero when nothing was kept).
  Eigen::Vector2d cg_a = Eigen::Vector2d::Zero();
  Eigen::Vector2d cg_b = Eigen::Vector2d::Zero();
  // True when the motion prior was applied.
  bool used_motion_prior = false;
  // Seed pair (input indices) from which the kept set grew; -1 when nothing was kept.
  int seed_i = -1;
  int seed_j = -1;
  // Ok, or why nothing was kept ("no seed pair with RoD <= 0.08 in 200 draws").
  Status status = Status::Ok();
};

// Ratio of difference of two centre-of-gravity vectors (eq. 4.19), the denominator at least
// `min_denominator_px` (IcgmOptions::motion_prior_rod_floor_px). Returns +infinity when the
// denominator is zero or any input is not finite, so such a pair never passes a threshold.
double RatioOfDifference(const Eigen::Vector2d& cgv_a, const Eigen::Vector2d& cgv_b,
                         double min_denominator_px = 0.0);

// One test of Algorithm 1's second loop: match `match` against the centres before the test,
// its RoD (eq. 4.19), whether it was kept, and the centres CG_0, CG_1 after the test.
struct IcgmStep {
  int match = -1;
  double rod = 0.0;
  bool kept = false;
  Eigen::Vector2d cg_a = Eigen::Vector2d::Zero();
  Eigen::Vector2d cg_b = Eigen::Vector2d::Zero();
};

// Algorithm 1 from the seed pair (seed_i, seed_j) chosen by the caller instead of drawn: the
// second loop alone, every other finite match tested once in input order against the
// incrementally updated centres, no refinement, no prior. RunIcgm with seed_pairs = 1 and
// refine = false returns exactly this for the seed pair it reports. `steps` (optional) receives
// one entry per tested match, in order. Never throws: indices out of range, equal, non-finite,
// or a seed pair with RoD > threshold give kept all zero and a non-ok status.
IcgmResult RunIcgmFromSeed(const std::vector<Eigen::Vector2d>& points_a,
                           const std::vector<Eigen::Vector2d>& points_b, int seed_i, int seed_j,
                           double threshold, std::vector<IcgmStep>* steps = nullptr);

// Runs ICGM on matches points_a[k] <-> points_b[k]. Never throws: different sizes, fewer than
// two usable matches, non-finite coordinates (such matches are never kept) or no consistent
// seed give a result with kept all zero (sized like the input) and a non-ok status.
// `predicted_b` (optional, sized like the input, NaN = no prediction) is the motion prior; it
// is used only with options.motion_prior.
IcgmResult RunIcgm(const std::vector<Eigen::Vector2d>& points_a,
                   const std::vector<Eigen::Vector2d>& points_b, const IcgmOptions& options,
                   const std::vector<Eigen::Vector2d>* predicted_b = nullptr);

}  // namespace icgm
