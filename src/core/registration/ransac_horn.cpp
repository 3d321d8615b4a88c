#include "core/registration/ransac_horn.h"

#include <algorithm>
#include <cmath>
#include <random>
#include <sstream>

#include "core/geometry/absolute_orientation.h"

namespace icgm {

int AdaptiveIterations(double inlier_ratio, int sample_size, double confidence, int cap) {
  if (inlier_ratio <= 0.0) return cap;
  if (inlier_ratio >= 1.0) return 1;
  const double all_inlier = std::pow(inlier_ratio, sample_size);
  const double denom = std::log1p(-all_inlier);
  if (!(denom < 0.0)) return cap;
  const double n = std::ceil(std::log1p(-confidence) / denom);
  if (!std::isfinite(n) || n > cap) return cap;
  return std::max(1, static_cast<int>(n));
}

namespace {

using Points = std::vector<Eigen::Vector3d>;

// Squared error of correspondence i under t, normalized so that <= 1 is an inlier; +inf when
// the image-space test fails outright (behind a camera, depths disagree).
double NormalizedError(const Eigen::Matrix3d& r, const Eigen::Vector3d& tr, const Points& src,
                       const Points& dst, size_t i, double threshold_sq,
                       const ReprojectionInlierTest* test) {
  const Eigen::Vector3d q = r * src[i] + tr;
  if (!test) return (q - dst[i]).squaredNorm() / threshold_sq;
  const Eigen::Vector3d back = r.transpose() * (dst[i] - tr);
  if (q.z() <= 1e-3 || back.z() <= 1e-3) return INFINITY;
  const double z = dst[i].z();
  if (std::abs(q.z() - z) > test->depth_abs_m + test->depth_rel_per_m * z * z) return INFINITY;
  const double s = test->sigma_px.empty() ? 1.0 : test->sigma_px[i];
  const double e = (test->intrinsics.Project(q) - test->dst_px[i]).squaredNorm() +
                   (test->intrinsics.Project(back) - test->src_px[i]).squaredNorm();
  return e / (2.0 * s * s * test->threshold_px * test->threshold_px);
}

// Inlier test over all correspondences; returns the inlier count and fills `inliers`.
size_t Classify(const Pose3& t, const Points& src, const Points& dst, double threshold_sq,
                const ReprojectionInlierTest* test, std::vector<int>* inliers, double* sum_sq) {
  inliers->clear();
  double sum = 0.0;
  const Eigen::Matrix3d r = t.linear();
  const Eigen::Vector3d tr = t.translation();
  for (size_t i = 0; i < src.size(); ++i) {
    const double e = NormalizedError(r, tr, src, dst, i, threshold_sq, test);
    if (e <= 1.0) {
      inliers->push_back(static_cast<int>(i));
      sum += e;
    }
  }
  if (sum_sq) *sum_sq = sum;
  return inliers->size();
}

bool FitSubset(const Points& src, const Points& dst, const std::vector<int>& idx, Pose3* out) {
  Points s, d;
  s.reserve(idx.size());
  d.reserve(idx.size());
  for (int i : idx) {
    s.push_back(src[i]);
    d.push_back(dst[i]);
  }
  SimilarityTransform sim;
  if (!HornAlign(s, d, false, &sim).ok()) return false;
  *out = sim.AsPose();
  return true;
}

// A minimal sample must span a triangle in both clouds; otherwise the rotation is undetermined.
bool NonDegenerate(const Points& p, int a, int b, int c, double min_spread) {
  const Eigen::Vector3d ab = p[b] - p[a];
  const Eigen::Vector3d ac = p[c] - p[a];
  if (ab.norm() < min_spread || ac.norm() < min_spread || (p[c] - p[b]).norm() < min_spread) {
    return false;
  }
  // Twice the triangle area against the squared spread: rejects near-collinear triples.
  return ab.cross(ac).norm() > 0.01 * std::max(ab.squaredNorm(), ac.squaredNorm());
}

// Least squares on the inliers of `t`, re-classified, repeated at most `rounds` times while the
// inlier count grows (or stays with a smaller residual); `t`, `inliers` and `sum_sq` hold the
// last accepted fit.
void RefitOnInliers(const Points& src, const Points& dst, double threshold_sq,
                    const ReprojectionInlierTest* test, int rounds, Pose3* t,
                    std::vector<int>* inliers, double* sum_sq) {
  std::vector<int> next;
  for (int round = 0; round < rounds; ++round) {
    Pose3 refined;
    if (!FitSubset(src, dst, *inliers, &refined)) return;
    double next_sum_sq = 0.0;
    Classify(refined, src, dst, threshold_sq, test, &next, &next_sum_sq);
    if (next.size() < inliers->size() ||
        (next.size() == inliers->size() && next_sum_sq >= *sum_sq)) {
      return;
    }
    const bool same = next == *inliers;
    *t = refined;
    inliers->swap(next);
    *sum_sq = next_sum_sq;
    if (same) return;
  }
}

}  // namespace

RansacResult RansacHorn(const Points& src, const Points& dst, const RansacOptions& options,
                        const ReprojectionInlierTest* test) {
  RansacResult result;
  const size_t n = src.size();
  if (dst.size() != n) {
    std::ostringstream s;
    s << "correspondence size mismatch: " << n << " source vs " << dst.size() << " destination";
    result.status = Status::Error(s.str());
    return result;
  }
  if (n < 3) {
    result.status = Status::Error("too few correspondences: " + std::to_string(n) + " < 3");
    return result;
  }
  const double thr_sq = options.inlier_threshold_m * options.inlier_threshold_m;
  std::mt19937_64 rng(options.rng_seed);
  std::uniform_int_distribution<int> pick(0, static_cast<int>(n) - 1);

  std::vector<int> best_inliers, inliers;
  Pose3 best = Pose3::Identity();
  double best_sum_sq = 0.0;
  int needed = std::max(1, options.max_iterations);
  int degenerate = 0;
  int it = 0;
  for (; it < needed && it < options.max_iterations; ++it) {
    int a = pick(rng), b = pick(rng), c = pick(rng);
    if (a == b || a == c || b == c || !NonDegenerate(src, a, b, c, options.min_sample_spread_m) ||
        !NonDegenerate(dst, a, b, c, options.min_sample_spread_m)) {
      ++degenerate;
      continue;
    }
    Pose3 hyp;
    if (!FitSubset(src, dst, {a, b, c}, &hyp)) {
      ++degenerate;
      continue;
    }
    double sum_sq = 0.0;
    const size_t count = Classify(hyp, src, dst, thr_sq, test, &inliers, &sum_sq);
    // Ties are broken by the residual so the tighter hypothesis wins (MSAC-like).
    if (count < best_inliers.size() || (count == best_inliers.size() && sum_sq >= best_sum_sq)) {
      continue;
    }
    if (options.local_optimization && count >= 3) {
      RefitOnInliers(src, dst, thr_sq, test, options.refine_rounds, &hyp, &inliers, &sum_sq);
    }
    best_inliers.swap(inliers);
    best = hyp;
    best_sum_sq = sum_sq;
    needed = AdaptiveIterations(static_cast<double>(best_inliers.size()) / n, 3, options.confidence,
                                options.max_iterations);
  }
  result.iterations = it;
  if (best_inliers.size() < 3) {
    std::ostringstream s;
    s << "no consistent hypothesis: best sample had " << best_inliers.size() << " inliers ("
      << degenerate << " of " << it << " samples degenerate)";
    result.status = Status::Error(s.str());
    return result;
  }

  // Refinement: least squares on all inliers, then re-classify with the refined transform.
  for (int round = 0; round < options.refine_rounds; ++round) {
    Pose3 refined;
    if (!FitSubset(src, dst, best_inliers, &refined)) break;
    Classify(refined, src, dst, thr_sq, test, &inliers, nullptr);
    if (inliers.size() < 3) break;
    const bool same = inliers == best_inliers;
    best = refined;
    best_inliers.swap(inliers);
    if (same) break;
  }

  double sum_sq = 0.0;
  for (int i : best_inliers) sum_sq += (best * src[i] - dst[i]).squaredNorm();
  result.transform = best;
  result.inliers = best_inliers;
  result.rmse_m = std::sqrt(sum_sq / best_inliers.size());
  if (static_cast<int>(best_inliers.size()) < options.min_inliers) {
    std::ostringstream s;
    s << "too few inliers: " << best_inliers.size() << " < " << options.min_inliers;
    result.status = Status::Error(s.str());
  }
  return result;
}

}  // namespace icgm
