#include "core/sim/crowd.h"

#include <algorithm>
#include <optional>

namespace icgm::sim {
namespace {

// The robot at frame k of a precomputed path: where it is, where it will be kCrowdLookaheadS
// later; the personal space of non-yielding walkers is kept from base_link.
CrowdRobot RobotAt(const std::vector<PlanarPose>& robot, size_t k, double dt_s) {
  CrowdRobot r;
  r.base = robot[k];
  r.base_ahead =
      robot[std::min(robot.size() - 1, k + static_cast<size_t>(kCrowdLookaheadS / dt_s))];
  r.camera_xy = Eigen::Vector2d(r.base.x_m, r.base.y_m);
  return r;
}

}  // namespace

Crowd::Crowd(const CrowdOptions& o, const StaticScene& scene, const std::vector<PlanarPose>& robot,
             double view_yaw_rad, double dt_s, double texel_size_m, Rng& rng) {
  std::optional<CrowdRobot> start;
  if (!robot.empty()) start = RobotAt(robot, 0, dt_s);
  CrowdStepper stepper(o, scene, start, view_yaw_rad, texel_size_m, rng);
  looks_ = stepper.looks();
  states_.reserve(robot.size());
  for (size_t k = 0; k < robot.size(); ++k) {
    if (k > 0) stepper.Step(RobotAt(robot, k, dt_s), dt_s);
    states_.push_back(stepper.States());
  }
}

void Crowd::AppendBodyParts(size_t frame, std::vector<CylinderPrimitive>* out) const {
  for (size_t i = 0; i < looks_.size(); ++i) {
    sim::AppendBodyParts(looks_[i], states_[frame][i], out);
  }
}

}  // namespace icgm::sim
