// Full pose-graph optimization of a HybridMap's keyframe poses with Ceres: an alternative back
// end to the thesis's eq. 6.4 semi-consensus correction. Minimizes, over the global poses L_n,
//   sum over links (from, to) of rho(|| information^(1/2) * e ||^2),
//   e = [t(E); 2 * vec(q(E))],  E = measured^-1 * (L_from^-1 * L_to),
// i.e. the error in the (translation, rotation) layout of the links' 6x6 information (the twist
// layout of se3_geodesic.h to first order). Each pose is parameterized as translation +
// unit quaternion (Eigen quaternion manifold). rho is the robust loss, applied to loop-closure
// links only (odometry links are trusted to be inliers). The gauge is fixed by holding the first
// keyframe of each session (or only the first keyframe of the map) at its current pose.
#pragma once

#include <string>
#include <vector>

#include "core/common/enum_names.h"
#include "core/common/pose.h"
#include "core/common/status.h"
#include "core/map/hybrid_map.h"

namespace icgm {

// Robust loss on loop links (`pose_graph.loss`).
enum class RobustLoss { kHuber, kCauchy, kNone };

template <>
struct EnumNames<RobustLoss> {
  static constexpr EnumName<RobustLoss> kNames[] = {
      {RobustLoss::kHuber, "huber"}, {RobustLoss::kCauchy, "cauchy"}, {RobustLoss::kNone, "none"}};
};

// Read from the `pose_graph:` section of config/map.yaml (map_options.h).
struct PoseGraphOptions {
  RobustLoss loss = RobustLoss::kHuber;
  double loss_scale_sigma = 3.0;  // loss scale in whitened units (sigmas of the link's noise)
  int max_iterations = 100;
  double max_solver_time_s = 10.0;
  double function_tolerance = 1e-8;  // relative cost change at which the solver stops
  bool fix_session_starts = true;    // false: only the map's first keyframe is held fixed
};

struct PoseGraphSummary {
  double initial_cost = 0.0;  // Ceres cost: half the sum of (robustified) squared residuals
  double final_cost = 0.0;
  int iterations = 0;
  double time_s = 0.0;
  int residual_blocks = 0;
  int fixed_keyframes = 0;
  std::string report;  // Ceres' one-line report
};

class PoseGraphOptimizer {
 public:
  explicit PoseGraphOptimizer(const PoseGraphOptions& options) : options_(options) {}

  // Whether this build has Ceres (without it Optimize always fails).
  static bool Available();

  // Optimizes the global poses of all keyframes of `map` over all its links, starting from the
  // current global poses. `extra_fixed` (optional, indexed by keyframe id, size map.size()) holds
  // further keyframes at their current pose. On success `poses` (indexed by keyframe id) holds
  // the optimized L_n; on failure (no Ceres, bad link, solver failure or no convergence within
  // max_iterations) `poses` holds the initial poses and the Status says why. `summary` is
  // optional and filled in both cases when the solver ran.
  Status Optimize(const HybridMap& map, std::vector<Pose3>* poses,
                  PoseGraphSummary* summary = nullptr,
                  const std::vector<bool>* extra_fixed = nullptr) const;

  const PoseGraphOptions& options() const { return options_; }

 private:
  PoseGraphOptions options_;
};

}  // namespace icgm
