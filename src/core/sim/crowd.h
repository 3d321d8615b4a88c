// Walking pedestrians recorded for a whole sequence at construction, so any frame can be
// rendered in any order: CrowdStepper's motion model stepped along a precomputed robot path.
#pragma once

#include <vector>

#include "core/sim/crowd_stepper.h"
#include "core/sim/loop_route.h"
#include "core/sim/pedestrian_model.h"
#include "core/sim/scene.h"
#include "core/sim/sim_options.h"

namespace icgm::sim {

class Crowd {
 public:
  Crowd() = default;
  // `robot` holds base_link's planar pose for each frame, frames dt_s apart; the camera looks
  // view_yaw_rad to the left of the robot's heading (crossing walkers aim across that view).
  // Non-yielding walkers keep their personal space from base_link's position here (for a
  // handheld camera `robot` is the camera itself).
  Crowd(const CrowdOptions& options, const StaticScene& scene, const std::vector<PlanarPose>& robot,
        double view_yaw_rad, double dt_s, double texel_size_m, Rng& rng);

  size_t num_pedestrians() const { return looks_.size(); }
  size_t num_frames() const { return states_.size(); }
  const PedestrianState& state(size_t frame, size_t pedestrian) const {
    return states_[frame][pedestrian];
  }
  // Appends the body parts of every pedestrian at `frame`.
  void AppendBodyParts(size_t frame, std::vector<CylinderPrimitive>* out) const;

 private:
  std::vector<PedestrianLook> looks_;
  std::vector<std::vector<PedestrianState>> states_;  // [frame][pedestrian]
};

}  // namespace icgm::sim
