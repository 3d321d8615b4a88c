#include "core/icgm/icgm_matcher.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>
#include <string>
#include <utility>

#include "core/common/option_reader.h"

namespace icgm {

void ReadOptions(const OptionReader& reader, IcgmOptions* options) {
  reader.Read("threshold", &options->threshold, 0.0, 1.0);
  reader.Read("auto_threshold", &options->auto_threshold);
  reader.Read("auto_threshold_min", &options->auto_threshold_min, 0.0, 1.0);
  reader.Read("auto_threshold_max", &options->auto_threshold_max, 0.0, 1.0);
  reader.Read("auto_threshold_scale", &options->auto_threshold_scale, 0.1, 100.0);
  reader.Read("seed_pairs", &options->seed_pairs, 1, 1000);
  reader.Read("max_seed_attempts", &options->max_seed_attempts, 1, 1000000);
  reader.Read("refine", &options->refine);
  reader.Read("max_refine_iterations", &options->max_refine_iterations, 0, 1000);
  reader.Read("motion_prior", &options->motion_prior);
  reader.Read("motion_prior_threshold", &options->motion_prior_threshold, 0.0, 1.0);
  reader.Read("motion_prior_tolerance_px", &options->motion_prior_tolerance_px, 0.0, 10000.0);
  reader.Read("motion_prior_rod_floor_px", &options->motion_prior_rod_floor_px, 0.0, 10000.0);
  int rng_seed = static_cast<int>(options->rng_seed);
  reader.Read("rng_seed", &rng_seed, 0, std::numeric_limits<int>::max());
  options->rng_seed = static_cast<uint64_t>(rng_seed);
  if (options->auto_threshold_min > options->auto_threshold_max) {
    throw LoadError(reader.path() + ": auto_threshold_min > auto_threshold_max");
  }
}

double RatioOfDifference(const Eigen::Vector2d& cgv_a, const Eigen::Vector2d& cgv_b,
                         double min_denominator_px) {
  const double denominator = std::max(cgv_a.norm() + cgv_b.norm(), min_denominator_px);
  // Not finite or zero: both vectors vanish (coincident points), the ratio is undefined.
  if (!(denominator > 0.0) || !std::isfinite(denominator)) {
    return std::numeric_limits<double>::infinity();
  }
  return (cgv_a - cgv_b).norm() / denominator;
}

namespace {

bool Finite(const Eigen::Vector2d& p) { return std::isfinite(p.x()) && std::isfinite(p.y()); }

// One consistent set: membership flags over all input matches and the running sums.
struct ConsistentSet {
  std::vector<uint8_t> kept;
  size_t count = 0;
  int seed_i = -1;
  int seed_j = -1;
  Eigen::Vector2d sum_a = Eigen::Vector2d::Zero();
  Eigen::Vector2d sum_b = Eigen::Vector2d::Zero();

  Eigen::Vector2d CgA() const { return sum_a / static_cast<double>(count); }
  Eigen::Vector2d CgB() const { return sum_b / static_cast<double>(count); }
};

class IcgmRunner {
 public:
  // `agreeing` (motion prior): the valid matches that agree with the prediction; seeds are
  // drawn among them (when there are two) and sets are ranked by how many they hold.
  IcgmRunner(const std::vector<Eigen::Vector2d>& a, const std::vector<Eigen::Vector2d>& b,
             const std::vector<int>& valid, uint64_t rng_seed,
             std::vector<int> agreeing = std::vector<int>(), double rod_floor_px = 0.0)
      : a_(a),
        b_(b),
        valid_(valid),
        rng_(rng_seed),
        agreeing_(std::move(agreeing)),
        rod_floor_px_(rod_floor_px) {}

  // Algorithm 1 first loop: random pairs until RoD(p_i - p_j, p'_i - p'_j) <= thr.
  bool DrawSeed(double thr, int max_attempts, int* i, int* j) {
    const std::vector<int>& pool = agreeing_.size() >= 2 ? agreeing_ : valid_;
    std::uniform_int_distribution<size_t> pick(0, pool.size() - 1);
    for (int attempt = 0; attempt < max_attempts; ++attempt) {
      const int s = pool[pick(rng_)];
      const int t = pool[pick(rng_)];
      if (s == t) continue;
      if (RatioOfDifference(a_[s] - a_[t], b_[s] - b_[t], rod_floor_px_) <= thr) {
        *i = s;
        *j = t;
        return true;
      }
    }
    return false;
  }

  // Algorithm 1 second loop: every other match tested once, in input order, against the
  // incrementally updated centres of gravity (eqs. 4.15-4.19). `steps` (optional): the trace.
  void GrowFromSeed(int i, int j, double thr, ConsistentSet* set,
                    std::vector<IcgmStep>* steps = nullptr) const {
    set->kept.assign(a_.size(), 0);
    set->kept[i] = set->kept[j] = 1;
    set->count = 2;
    set->seed_i = i;
    set->seed_j = j;
    set->sum_a = a_[i] + a_[j];
    set->sum_b = b_[i] + b_[j];
    Eigen::Vector2d cg_a = set->CgA();
    Eigen::Vector2d cg_b = set->CgB();
    for (const int k : valid_) {
      if (k == i || k == j) continue;
      const double rod = RatioOfDifference(cg_a - a_[k], cg_b - b_[k], rod_floor_px_);
      if (rod <= thr) {
        set->kept[k] = 1;
        ++set->count;
        set->sum_a += a_[k];
        set->sum_b += b_[k];
        // Same as CG <- SCG/(SCG+1) * (CG + p_k/SCG) of Algorithm 1, without drift.
        cg_a = set->CgA();
        cg_b = set->CgB();
      }
      if (steps) steps->push_back({k, rod, rod <= thr, cg_a, cg_b});
    }
  }

  // Re-tests every match against the centres of the current set until the set is a fixed
  // point, which removes the dependence on input order. `scratch` avoids reallocation.
  void Refine(double thr, int max_iterations, ConsistentSet* set, ConsistentSet* scratch) const {
    for (int iteration = 0; iteration < max_iterations; ++iteration) {
      const Eigen::Vector2d cg_a = set->CgA();
      const Eigen::Vector2d cg_b = set->CgB();
      scratch->kept.assign(a_.size(), 0);
      scratch->count = 0;
      scratch->sum_a.setZero();
      scratch->sum_b.setZero();
      scratch->seed_i = set->seed_i;
      scratch->seed_j = set->seed_j;
      for (const int k : valid_) {
        if (RatioOfDifference(cg_a - a_[k], cg_b - b_[k], rod_floor_px_) <= thr) {
          scratch->kept[k] = 1;
          ++scratch->count;
          scratch->sum_a += a_[k];
          scratch->sum_b += b_[k];
        }
      }
      // A set that collapses below a pair is no improvement; keep the previous one.
      if (scratch->count < 2) return;
      const bool same = scratch->kept == set->kept;
      std::swap(*set, *scratch);
      if (same) return;
    }
  }

  // Largest consistent set over `seed_pairs` seeds (with a motion prior: the one holding most
  // agreeing matches, then the largest); false when no seed pair was found.
  bool Best(double thr, int seed_pairs, int max_attempts, bool refine, int max_refine,
            ConsistentSet* best) {
    ConsistentSet candidate;
    ConsistentSet scratch;
    bool found = false;
    size_t best_agreeing = 0;
    for (int s = 0; s < seed_pairs; ++s) {
      int i = -1;
      int j = -1;
      if (!DrawSeed(thr, max_attempts, &i, &j)) continue;
      GrowFromSeed(i, j, thr, &candidate);
      if (refine) Refine(thr, max_refine, &candidate, &scratch);
      const size_t agreeing = Agreeing(candidate);
      if (!found || agreeing > best_agreeing ||
          (agreeing == best_agreeing && candidate.count > best->count)) {
        std::swap(*best, candidate);
        best_agreeing = agreeing;
        found = true;
      }
      // Nothing can beat a set holding every usable match.
      if (best->count == valid_.size()) break;
    }
    return found;
  }

 private:
  // Members of `set` that agree with the motion prior (0 without one).
  size_t Agreeing(const ConsistentSet& set) const {
    size_t n = 0;
    for (const int k : agreeing_) n += set.kept[k];
    return n;
  }

  const std::vector<Eigen::Vector2d>& a_;
  const std::vector<Eigen::Vector2d>& b_;
  const std::vector<int>& valid_;
  std::mt19937_64 rng_;
  const std::vector<int> agreeing_;
  // Minimum RoD denominator (motion prior only; 0: eq. 4.19).
  const double rod_floor_px_;
};

// Automatic Thr, the knee of the kept-count curve of thesis Fig. 5.1: the number of kept
// matches N(Thr) rises while Thr admits more of the static structure, levels off once all of it
// is in, and rises again only when moving objects start to pass. Thr runs over a geometric grid
// from auto_threshold_min to auto_threshold_max; the first grid value after which N grows by
// less than kPlateauGrowth over the next kPlateauSteps steps is the knee, and Thr is the knee
// times auto_threshold_scale (clamped), a margin for noisier image pairs. Plateaus holding less
// than kMinShare of the count at the loosest Thr are skipped: at a Thr below the static RoD
// (e.g. a large in-plane rotation) a rigidly moving object can form the only consistent set.
double AutoThreshold(IcgmRunner* runner, const IcgmOptions& options) {
  constexpr double kGridRatio = 1.2;
  constexpr double kPlateauGrowth = 0.03;
  constexpr int kPlateauSteps = 2;
  constexpr int kSeeds = 3;
  constexpr int kRefineSweeps = 3;
  constexpr double kMinShare = 0.5;
  const int attempts = std::max(1, options.max_seed_attempts);
  const double lo = std::max(1e-4, options.auto_threshold_min);
  const double hi = std::max(lo, options.auto_threshold_max);
  std::vector<double> grid;
  for (double t = lo; t < hi * kGridRatio; t *= kGridRatio) grid.push_back(std::min(t, hi));
  // Counts are evaluated lazily: the knee is usually found after a few grid values.
  std::vector<long> counts(grid.size(), -1);
  ConsistentSet set;
  auto count_at = [&](size_t g) {
    if (counts[g] < 0) {
      counts[g] = runner->Best(grid[g], kSeeds, attempts, true, kRefineSweeps, &set)
                      ? static_cast<long>(set.count)
                      : 0;
    }
    return static_cast<double>(counts[g]);
  };
  // N grows with Thr, so N at the loosest Thr stands for the largest count.
  const double reference = count_at(grid.size() - 1);
  for (size_t g = 0; g + kPlateauSteps < grid.size(); ++g) {
    const double n = count_at(g);
    if (n < 2 || n < kMinShare * reference) continue;
    if (count_at(g + kPlateauSteps) <= n * (1.0 + kPlateauGrowth)) {
      return std::clamp(grid[g] * options.auto_threshold_scale, lo, hi);
    }
  }
  return hi;
}

std::string Num(double v) {
  char buffer[32];
  std::snprintf(buffer, sizeof(buffer), "%.4g", v);
  return buffer;
}

}  // namespace

IcgmResult RunIcgmFromSeed(const std::vector<Eigen::Vector2d>& points_a,
                           const std::vector<Eigen::Vector2d>& points_b, int seed_i, int seed_j,
                           double threshold, std::vector<IcgmStep>* steps) {
  IcgmResult result;
  result.kept.assign(points_a.size(), 0);
  result.threshold_used = threshold;
  const int n = static_cast<int>(points_a.size());
  if (points_a.size() != points_b.size()) {
    result.status = Status::Error("icgm: " + std::to_string(points_a.size()) + " points in a but " +
                                  std::to_string(points_b.size()) + " in b");
    return result;
  }
  const auto usable = [&](int k) {
    return k >= 0 && k < n && Finite(points_a[k]) && Finite(points_b[k]);
  };
  if (!usable(seed_i) || !usable(seed_j) || seed_i == seed_j) {
    result.status = Status::Error("icgm: seed pair (" + std::to_string(seed_i) + ", " +
                                  std::to_string(seed_j) + ") is not two distinct usable matches");
    return result;
  }
  const double seed_rod =
      RatioOfDifference(points_a[seed_i] - points_a[seed_j], points_b[seed_i] - points_b[seed_j]);
  if (!(seed_rod <= threshold)) {
    result.status =
        Status::Error("icgm: seed pair RoD " + Num(seed_rod) + " > Thr " + Num(threshold));
    return result;
  }
  std::vector<int> valid;
  for (int k = 0; k < n; ++k) {
    if (usable(k)) valid.push_back(k);
  }
  IcgmRunner runner(points_a, points_b, valid, 0);
  ConsistentSet set;
  runner.GrowFromSeed(seed_i, seed_j, threshold, &set, steps);
  result.kept = std::move(set.kept);
  result.num_kept = set.count;
  result.seed_i = seed_i;
  result.seed_j = seed_j;
  result.cg_a = set.CgA();
  result.cg_b = set.CgB();
  return result;
}

IcgmResult RunIcgm(const std::vector<Eigen::Vector2d>& points_a,
                   const std::vector<Eigen::Vector2d>& points_b, const IcgmOptions& options,
                   const std::vector<Eigen::Vector2d>* predicted_b) {
  IcgmResult result;
  result.kept.assign(points_a.size(), 0);
  result.threshold_used = options.threshold;
  if (points_a.size() != points_b.size()) {
    result.status = Status::Error("icgm: " + std::to_string(points_a.size()) + " points in a but " +
                                  std::to_string(points_b.size()) + " in b");
    return result;
  }
  std::vector<int> valid;
  valid.reserve(points_a.size());
  // Motion prior: predicted positions replace those of image a (see the header).
  std::vector<int> agreeing;
  const bool prior = options.motion_prior && predicted_b &&
                     predicted_b->size() == points_a.size() &&
                     std::count_if(predicted_b->begin(), predicted_b->end(), Finite) >= 2;
  const std::vector<Eigen::Vector2d>& from = prior ? *predicted_b : points_a;
  for (size_t k = 0; k < points_a.size(); ++k) {
    if (!Finite(points_a[k]) || !Finite(from[k]) || !Finite(points_b[k])) continue;
    valid.push_back(static_cast<int>(k));
    if (prior && (from[k] - points_b[k]).norm() <= options.motion_prior_tolerance_px) {
      agreeing.push_back(static_cast<int>(k));
    }
  }
  if (valid.size() < 2) {
    result.status = Status::Error("icgm: " + std::to_string(valid.size()) + " usable matches < 2");
    return result;
  }

  IcgmRunner runner(from, points_b, valid, options.rng_seed, std::move(agreeing),
                    prior ? options.motion_prior_rod_floor_px : 0.0);
  const int seed_pairs = std::max(1, options.seed_pairs);
  const int attempts = std::max(1, options.max_seed_attempts);
  double thr = options.threshold;
  if (prior) {
    thr = options.motion_prior_threshold;
    result.threshold_used = thr;
    result.used_motion_prior = true;
  } else if (options.auto_threshold) {
    thr = AutoThreshold(&runner, options);
    result.threshold_used = thr;
  }

  ConsistentSet best;
  if (!runner.Best(thr, seed_pairs, attempts, options.refine, options.max_refine_iterations,
                   &best)) {
    result.status = Status::Error("icgm: no seed pair with RoD <= " + Num(thr) + " in " +
                                  std::to_string(attempts) + " draws");
    return result;
  }
  result.kept = std::move(best.kept);
  result.num_kept = best.count;
  result.seed_i = best.seed_i;
  result.seed_j = best.seed_j;
  // With the prior, the centre in image a is the one of the kept matches' own positions.
  if (prior) {
    Eigen::Vector2d sum = Eigen::Vector2d::Zero();
    for (size_t k = 0; k < points_a.size(); ++k) {
      if (result.kept[k]) sum += points_a[k];
    }
    best.sum_a = sum;
  }
  result.cg_a = best.CgA();
  result.cg_b = best.CgB();
  return result;
}

}  // namespace icgm
