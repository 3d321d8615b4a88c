// Local planning around obstacles with OMPL: RRT-Connect in SE(2) within a square window around
// the robot, states valid where the obstacle grid leaves the footprint its clearance, the path
// shortened by OMPL's simplifier and sampled densely. Used when the route ahead is blocked; the
// goal is a free route point ahead (chosen by the caller).
//
// Deterministic: a plan is a function of its inputs (start, goal, grid) and the options only.
// Every Plan seeds its own random streams (the state sampler, the planner's and the
// simplifier's) from `seed`, planning stops after max_state_checks state validity checks (a
// work budget, not a time budget) and the simplifier runs a fixed number of steps. The wall
// clock only serves as a safety stop (time_cap_ms) that is reported when it ends planning.
#pragma once

#include <memory>
#include <vector>

#include <Eigen/Core>

#include "core/common/status.h"
#include "core/nav/obstacle_grid.h"
#include "core/nav/planar_pose.h"

namespace icgm {

struct LocalPlannerOptions {
  double window_m = 6.0;          // side of the square search window centred between start and goal
  // Work budget of RRT-Connect: it gives up after this many state validity checks.
  int max_state_checks = 20000;
  int simplify_steps = 50;        // shortcut attempts of the simplifier (fixed: deterministic)
  // Safety stop on the wall clock: planning ends after this long whatever the budget left (then
  // the result depends on the machine's load; LocalPathStats::time_cap_hit says so).
  double time_cap_ms = 500.0;
  double range_m = 0.5;           // RRT-Connect's extension step
  double check_resolution_m = 0.03;  // motion validity checked every this far
  double sample_spacing_m = 0.05;    // the returned path's waypoint spacing
  // Near the start the robot may already be inside the inflation (a walker came close): states
  // within this distance of the start need only the footprint itself to be free.
  double start_escape_m = 0.5;
  int seed = 1;  // seeds every plan's random streams (the same input gives the same plan)
};

// What one Plan call cost.
struct LocalPlanStats {
  int state_checks = 0;       // validity checks while planning (<= max_state_checks)
  bool time_cap_hit = false;  // the wall-clock safety stop ended planning (not deterministic)
};

struct LocalPath {
  std::vector<Eigen::Vector2d> points_m;  // start .. goal, sample_spacing_m apart
  double length_m = 0.0;
};

class LocalPlanner {
 public:
  explicit LocalPlanner(LocalPlannerOptions options = LocalPlannerOptions());
  ~LocalPlanner();

  // A collision-free path from `start` to `goal` (map frame). Fails with the reason (goal or
  // start blocked, no path within the work budget, or the time cap hit). `stats` may be null.
  // `clearance_m`: kept beyond the footprint outside the start's escape (negative: the grid's).
  Status Plan(const Pose2D& start, const Pose2D& goal, const ObstacleGrid& grid, LocalPath* path,
              LocalPlanStats* stats = nullptr, double clearance_m = -1.0) const;
  // True when the footprint is free along the straight segment a -> b (inflated clearance, or
  // the bare footprint within start_escape_m of a).
  bool SegmentFree(const Eigen::Vector2d& a, const Eigen::Vector2d& b,
                   const ObstacleGrid& grid) const;
  // The same with the escape measured from `escape_from` (the robot) instead of a: a piece of a
  // path farther along keeps `clearance_m` beyond the footprint (negative: the grid's inflated
  // clearance).
  bool SegmentFree(const Eigen::Vector2d& a, const Eigen::Vector2d& b, const ObstacleGrid& grid,
                   const Eigen::Vector2d& escape_from, double clearance_m = -1.0) const;
  const LocalPlannerOptions& options() const { return options_; }

 private:
  // `required_m`: the centre's distance from the cells that counts as free away from the start
  // (negative: the grid's inflation).
  bool StateFree(const Eigen::Vector2d& p, const Eigen::Vector2d& start, const ObstacleGrid& grid,
                 double required_m = -1.0) const;
  LocalPlannerOptions options_;
};

// Arc length of a polyline.
double PolylineLength(const std::vector<Eigen::Vector2d>& points);
// The polyline resampled every `spacing_m` (first and last points kept).
std::vector<Eigen::Vector2d> ResamplePolyline(const std::vector<Eigen::Vector2d>& points,
                                              double spacing_m);

}  // namespace icgm
