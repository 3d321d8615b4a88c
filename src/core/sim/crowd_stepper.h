// The pedestrians' motion model, one time step at a time. Each walker heads for a waypoint (a
// random free spot, or with probability crossing_fraction a spot that makes it cross a few
// metres in front of the camera), steers around furniture and other walkers, and yields to the
// robot: no body part comes closer than robot_clearance_m to base_link. Non-yielding walkers
// (non_yielding_fraction) walk past it without giving way, keeping only personal_space_m from the
// camera (fixed route) or, when CrowdRobot::footprint_radius_m > 0 (closed loop), from the robot's
// body: they see it from every side and do not step into it, but they do not make room for it
// either, so a robot driving into one touches it.
// Crowd records it for a precomputed robot path; ClosedLoopSimulator steps it with the robot's
// current pose.
#pragma once

#include <optional>
#include <vector>

#include <Eigen/Core>

#include "core/sim/loop_route.h"
#include "core/sim/pedestrian_model.h"
#include "core/sim/scene.h"
#include "core/sim/sim_options.h"

namespace icgm::sim {

// What the crowd knows of the robot at one instant.
struct CrowdRobot {
  // base_link now: yielding walkers keep robot_clearance_m from it.
  PlanarPose base;
  // Where base_link will be in about kCrowdLookaheadS: crossing walkers aim across the camera's
  // view from there.
  PlanarPose base_ahead;
  // The camera's position on the floor: non-yielding walkers keep personal_space_m from it.
  Eigen::Vector2d camera_xy = Eigen::Vector2d::Zero();
  // > 0: the robot's body, a disc of this radius around base_link. Non-yielding walkers keep
  // personal_space_m from its edge in their own steps and are not pushed by it.
  // <= 0: they keep personal_space_m from camera_xy and are pushed out of that circle.
  double footprint_radius_m = 0.0;
};

// How far ahead crossing walkers anticipate the robot.
constexpr double kCrowdLookaheadS = 3.0;

class CrowdStepper {
 public:
  CrowdStepper() = default;
  // Draws the walkers' looks, speeds, start positions and first goals from `rng` (crossing
  // walkers start ahead of `robot`'s camera view; without a robot they start anywhere). The
  // camera looks view_yaw_rad to the left of the robot's heading.
  CrowdStepper(const CrowdOptions& options, const StaticScene& scene,
               const std::optional<CrowdRobot>& robot, double view_yaw_rad, double texel_size_m,
               Rng rng);

  // Moves every walker by dt_s seconds (in sub-steps of at most 0.05 s) given the robot's pose
  // at the end of the step.
  void Step(const CrowdRobot& robot, double dt_s);

  size_t num_pedestrians() const { return walkers_.size(); }
  const std::vector<PedestrianLook>& looks() const { return looks_; }
  std::vector<PedestrianState> States() const;
  // Radius of a disc on the floor containing pedestrian i's body.
  float radius_m(size_t i) const { return walkers_[i].radius; }
  // Whether pedestrian i gives way to the robot (CrowdOptions::non_yielding_fraction).
  bool yields(size_t i) const { return walkers_[i].yields; }
  // Appends the body parts of every pedestrian now.
  void AppendBodyParts(std::vector<CylinderPrimitive>* out) const;

 private:
  struct Walker {
    Eigen::Vector2f p = Eigen::Vector2f::Zero();
    Eigen::Vector2f goal = Eigen::Vector2f::Zero();
    float heading = 0.0f;
    float phase = 0.0f;
    float swing = 0.0f;
    float preferred_speed = 1.0f;
    float radius = 0.3f;
    float stuck_s = 0.0f;
    // false: walks past the camera as if it were not there (keeps only the personal space).
    bool yields = true;
  };
  void ChooseGoal(const std::optional<CrowdRobot>& robot, Walker* w);
  void MoveWalker(const CrowdRobot& robot, size_t self, float dt);

  CrowdOptions options_;
  StaticScene scene_;
  float view_yaw_rad_ = 0.0f;
  Rng rng_;
  std::vector<PedestrianLook> looks_;
  std::vector<Walker> walkers_;
};

}  // namespace icgm::sim
