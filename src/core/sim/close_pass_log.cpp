#include "core/sim/close_pass_log.h"

#include <algorithm>
#include <cmath>

namespace icgm::sim {

ClosePassLog::ClosePassLog(ClosePassOptions options) : options_(options) {}

void ClosePassLog::Step(double t_s, const Eigen::Vector2d& robot_before,
                        const Eigen::Vector2d& robot_after, double robot_speed_mps,
                        double robot_radius_m, const std::vector<Eigen::Vector2d>& walkers_before,
                        const std::vector<Eigen::Vector2d>& walkers_after,
                        const std::vector<double>& walker_radii_m, const std::string& context) {
  const size_t n = std::min({walkers_before.size(), walkers_after.size(), walker_radii_m.size()});
  if (approach_.size() != n) approach_.assign(n, Approach());
  size_t nearest = 0;
  double nearest_m = 1e9;
  for (size_t i = 0; i < n; ++i) {
    const double before = (walkers_before[i] - robot_before).norm();
    const double clearance_before = before - walker_radii_m[i] - robot_radius_m;
    const double clearance =
        (walkers_after[i] - robot_after).norm() - walker_radii_m[i] - robot_radius_m;
    Approach& a = approach_[i];
    if (clearance < options_.approach_m) {
      if (!a.inside) a = Approach{true, 0.0, 0.0, 0.0, 0.0};
      // Each party's motion with the other held where it was before the step.
      const double robot_m = before - (walkers_before[i] - robot_after).norm();
      const double walker_m = before - (walkers_after[i] - robot_before).norm();
      a.robot_m += robot_m;
      a.walker_m += walker_m;
      if (clearance < options_.clearance_m) {
        // The part of this step's change below clearance_m, shared in proportion.
        const double fraction =
            clearance_before > options_.clearance_m && clearance_before > clearance
                ? (options_.clearance_m - clearance) / (clearance_before - clearance)
                : 1.0;
        a.robot_inside_m += fraction * robot_m;
        a.walker_inside_m += fraction * walker_m;
      } else {
        a.robot_inside_m = a.walker_inside_m = 0.0;
      }
    } else {
      a.inside = false;
    }
    if (clearance < nearest_m) {
      nearest_m = clearance;
      nearest = i;
    }
  }
  if (n == 0) return;
  min_clearance_m_ = std::min(min_clearance_m_, nearest_m);
  if (nearest_m >= options_.clearance_m) {
    open_ = -1;
    return;
  }
  if (open_ < 0) {
    ClosePass pass;
    pass.start_s = t_s;
    pass.min_clearance_m = 1e9;
    pass.walker = nearest;
    pass.robot_speed_mps = robot_speed_mps;
    pass.robot_standing = std::abs(robot_speed_mps) < options_.standing_mps;
    pass.context = context;
    passes_.push_back(pass);
    open_ = static_cast<int>(passes_.size()) - 1;
  }
  ClosePass& pass = passes_[open_];
  if (nearest_m < pass.min_clearance_m) {
    pass.min_clearance_m = nearest_m;
    pass.min_at_s = t_s;
    pass.walker = nearest;
    pass.robot_closed_m = approach_[nearest].robot_m;
    pass.walker_closed_m = approach_[nearest].walker_m;
    pass.robot_inside_m = approach_[nearest].robot_inside_m;
    pass.walker_inside_m = approach_[nearest].walker_inside_m;
  }
}

int ClosePassLog::standing() const {
  return static_cast<int>(std::count_if(passes_.begin(), passes_.end(),
                                        [](const ClosePass& p) { return p.robot_standing; }));
}

int ClosePassLog::robot_closed_more() const {
  return static_cast<int>(std::count_if(passes_.begin(), passes_.end(), [](const ClosePass& p) {
    return p.robot_moving() && p.robot_closed_more();
  }));
}

int ClosePassLog::robot_inside_more() const {
  return static_cast<int>(std::count_if(passes_.begin(), passes_.end(), [](const ClosePass& p) {
    return p.robot_moving() && p.robot_inside_m > p.walker_inside_m;
  }));
}

}  // namespace icgm::sim
