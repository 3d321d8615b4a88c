// Close passes between the robot and walkers, with who closed the gap: every episode in which a
// walker's body comes closer than clearance_m to the robot's footprint (a disc), from the step it
// begins until the walker is clearance_m or more away again. For each walker within approach_m of
// the footprint the log sums, step by step, how much the gap shrank by the robot's own motion
// (the walker held where it was) and by the walker's (the robot held where it was); an episode
// takes the sums of its walker from where that walker came within approach_m down to the
// episode's closest point, and apart the shares of the part below clearance_m (from the step
// that crossed it, that step counted in proportion). An episode whose robot was standing when it
// began (true speed below standing_mps) is a walker walking into the robot; otherwise the shares
// say whether the robot drove into the walker's space or the walker closed in on a moving robot.
// Ground truth only: positions are the simulator's.
#pragma once

#include <string>
#include <vector>

#include <Eigen/Core>

namespace icgm::sim {

struct ClosePassOptions {
  double clearance_m = 0.3;    // an episode: a walker closer than this to the footprint
  double approach_m = 1.0;     // the closing shares are summed from this clearance down
  double standing_mps = 0.05;  // a robot slower than this when an episode begins stands
};

struct ClosePass {
  double start_s = 0.0;          // when the walker came closer than clearance_m
  double min_clearance_m = 0.0;  // closest during the episode
  double min_at_s = 0.0;
  size_t walker = 0;             // index of the walker
  double robot_speed_mps = 0.0;  // the robot's true speed when the episode began (signed)
  bool robot_standing = false;
  // The gap closed by the robot's and by the walker's motion, from approach_m down to the
  // episode's closest point (m; negative: that party opened the gap on balance).
  double robot_closed_m = 0.0;
  double walker_closed_m = 0.0;
  // The same below clearance_m only: from clearance_m down to the closest point.
  double robot_inside_m = 0.0;
  double walker_inside_m = 0.0;
  std::string context;  // what the caller said of the robot when the episode began
  bool robot_moving() const { return !robot_standing; }
  // The robot moved, and its motion closed more of the gap than the walker's.
  bool robot_closed_more() const { return robot_closed_m > walker_closed_m; }
};

class ClosePassLog {
 public:
  explicit ClosePassLog(ClosePassOptions options = ClosePassOptions());

  // One simulator step from `*_before` to `*_after` (the robot's base and every walker; the
  // walkers in the same order every step), the robot's true speed over it and the footprint's
  // and the walkers' radii. `context` is kept with an episode that begins in this step.
  void Step(double t_s, const Eigen::Vector2d& robot_before, const Eigen::Vector2d& robot_after,
            double robot_speed_mps, double robot_radius_m,
            const std::vector<Eigen::Vector2d>& walkers_before,
            const std::vector<Eigen::Vector2d>& walkers_after,
            const std::vector<double>& walker_radii_m, const std::string& context);

  // Every episode so far (the last one may still be open).
  const std::vector<ClosePass>& passes() const { return passes_; }
  // Counts over the episodes: robot standing when it began; robot moving and its motion closed
  // more of the gap.
  int standing() const;
  int robot_closed_more() const;
  // Robot moving and its motion took more of the gap below clearance_m than the walker's.
  int robot_inside_more() const;
  double min_clearance_m() const { return min_clearance_m_; }
  const ClosePassOptions& options() const { return options_; }

 private:
  struct Approach {
    bool inside = false;  // within approach_m
    double robot_m = 0.0, walker_m = 0.0;
    double robot_inside_m = 0.0, walker_inside_m = 0.0;  // below clearance_m
  };
  ClosePassOptions options_;
  std::vector<Approach> approach_;  // per walker
  std::vector<ClosePass> passes_;
  int open_ = -1;         // index into passes_ of the episode under way
  bool closing_ = false;  // the open episode has not passed its closest point yet
  double min_clearance_m_ = 1e9;
};

}  // namespace icgm::sim
