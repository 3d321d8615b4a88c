// A closed-loop variant of the simulator: instead of driving a precomputed route, the robot
// executes velocity commands one step at a time, so a navigation stack can drive it. The world
// (room, furniture), the camera mount, the sensor models and the crowd come from the same
// SimOptions (scenario YAML) as for Simulator; pedestrians react to the robot's current pose.
//
// Each Step(cmd, dt):
//  1. limits the command to drive.max_{linear,angular}_* (speed) and moves the achieved
//     velocities towards it by at most drive.max_*_accel_* * dt (acceleration), then perturbs
//     them with actuation noise (relative sigma drive.*_noise_fraction),
//  2. integrates the true planar pose of base_link exactly along the arc (unicycle model),
//  3. integrates the wheel odometry with the OdometryNoiseOptions error model (distance scale
//     error, heading bias per metre, noise growing with sqrt(distance)),
//  4. steps the crowd by dt: yielding walkers keep crowd.robot_clearance_m from base_link,
//     non-yielding ones (crowd.non_yielding_fraction) only crowd.personal_space_m from the footprint,
//  5. counts collisions of the robot's footprint (a disc of drive.robot_radius_m around
//     base_link) with walls and furniture, and with pedestrians' bodies,
//  6. advances the time stamp by dt.
// The simulator does not stop the robot at obstacles: it drives through them and counts contacts
// (a camera outside the room renders a meaningless but well-defined image).
//
// Frames as in Simulator: world (z up, floor z = 0) -> base_link -> camera_rgb_optical_frame;
// odom coincides with base_link at the start. Only wheeled scenarios (camera_motion: wheeled).
// Everything is a deterministic function of the options (seed: world, odometry, actuation and
// sensor noise; crowd_seed: the crowd) and the sequence of commands and time steps.
#pragma once

#include <cstddef>
#include <limits>
#include <optional>
#include <vector>

#include "core/common/camera.h"
#include "core/common/planar_scan.h"
#include "core/common/pose.h"
#include "core/common/time.h"
#include "core/common/velocity_command.h"
#include "core/sim/crowd_stepper.h"
#include "core/sim/loop_route.h"
#include "core/sim/ray_caster.h"
#include "core/sim/scene.h"
#include "core/sim/sim_options.h"
#include "core/sim/simulator.h"
#include "core/sim/wheel_odometry.h"

namespace icgm::sim {

using icgm::VelocityCommand;

// Contacts of the robot's footprint with one kind of obstacle.
struct CollisionStats {
  // Distinct contact events: counted when the footprint starts touching, however long the
  // contact lasts (each pedestrian separately; walls and furniture together as one obstacle).
  int collisions = 0;
  // Smallest distance between the footprint's edge and the obstacle so far (negative while
  // overlapping); +infinity while there was none.
  double min_clearance_m = std::numeric_limits<double>::infinity();
};

class ClosedLoopSimulator {
 public:
  // Builds the world of `options` (as Simulator does for the same options: same room and
  // furniture for the same seed), places the robot at rest at `start` (default: the route's
  // start pose, where Simulator's robot starts) and the crowd around it. Throws LoadError for a
  // handheld scenario or invalid intrinsics.
  explicit ClosedLoopSimulator(const SimOptions& options,
                               const std::optional<PlanarPose>& start = std::nullopt);

  // Executes `cmd` for dt_s > 0 seconds (see the header comment). Call with the step of the
  // control loop (e.g. 0.1 s); steps longer than 0.05 s are integrated in sub-steps.
  void Step(const VelocityCommand& cmd, double dt_s);

  // Renders the current state: camera image, depth and dynamic mask, ground truth poses and
  // the wheel odometry sample (velocities: those of the last step as the wheels measured them).
  // SimFrame::index is the number of steps taken. Thread-compatible (const).
  SimFrame Render(const RenderFlags& flags = RenderFlags()) const;

  // The planar scanner's scan of the current state (options().scanner; rendered whether or not
  // `enabled` is set), stamped now; its range noise depends on the seed and the step count only.
  // T_base_scanner() places it on the base.
  PlanarScan RenderScan() const;
  Pose3 T_base_scanner() const;

  // --- Ground truth and state ---
  Time stamp() const { return stamp_; }
  double elapsed_s() const { return elapsed_s_; }
  size_t num_steps() const { return num_steps_; }
  // base_link's true planar pose in the world and as a 3D pose (on the floor).
  const PlanarPose& planar_pose() const { return pose_; }
  Pose3 T_world_base() const;
  Pose3 T_world_camera() const { return T_world_base() * T_base_camera_; }
  // The velocities the base actually moves with (after limits and actuation noise).
  const VelocityCommand& true_velocity() const { return velocity_; }
  // Wheel odometry (odom -> base_link, measured velocities), as of the last step.
  const OdometrySample& odometry() const { return odometry_.sample(); }
  // Distance driven so far (true, along the path).
  double distance_driven_m() const { return distance_m_; }

  const Pose3& T_base_camera() const { return T_base_camera_; }
  const CameraIntrinsics& intrinsics() const { return options_.intrinsics; }
  const SimOptions& options() const { return options_; }
  const StaticScene& scene() const { return scene_; }
  // The scenario's route (start pose; the furniture keeps it clear).
  const LoopRoute& route() const { return route_; }
  // Pedestrians now (positions, headings, gait), and their body radius (BodyRadius).
  size_t num_pedestrians() const { return crowd_.num_pedestrians(); }
  std::vector<PedestrianState> pedestrians() const { return crowd_.States(); }
  float pedestrian_radius_m(size_t i) const { return crowd_.radius_m(i); }
  bool pedestrian_yields(size_t i) const { return crowd_.yields(i); }

  // --- Collisions of the footprint (disc of options().drive.robot_radius_m) ---
  // Walls and furniture, pedestrians, and both together (collisions: sum; clearance: min).
  const CollisionStats& static_collisions() const { return static_stats_; }
  const CollisionStats& pedestrian_collisions() const { return people_stats_; }
  int collisions() const { return static_stats_.collisions + people_stats_.collisions; }
  double min_clearance_m() const;
  // Clearance between the footprint and the nearest wall or furniture, and nearest pedestrian's
  // body, at the current state (negative: overlapping).
  double StaticClearanceM() const;
  double PedestrianClearanceM() const;

 private:
  void StepRobot(const VelocityCommand& cmd, double dt_s);
  void UpdateCollisions();
  CrowdRobot CrowdView() const;

  SimOptions options_;
  LoopRoute route_;
  Pose3 T_base_camera_;
  StaticScene scene_;
  CrowdStepper crowd_;
  RayCaster caster_;
  Rng drive_rng_;
  Rng odometry_rng_;

  Time stamp_;
  double elapsed_s_ = 0.0;
  size_t num_steps_ = 0;
  PlanarPose pose_;
  // The limited command the base follows (without actuation noise) and the velocity it moves
  // with (with it).
  VelocityCommand ramped_;
  VelocityCommand velocity_;
  double distance_m_ = 0.0;
  WheelOdometryIntegrator odometry_;

  CollisionStats static_stats_;
  CollisionStats people_stats_;
  bool static_contact_ = false;
  std::vector<bool> person_contact_;
};

}  // namespace icgm::sim
