// The dynamic-scene RGB-D simulator: a robot with a Kinect-like camera on base_link drives loops
// through a furnished cafeteria full of walking pedestrians, or (camera_motion: handheld) a
// person holds the camera in a room. Construction builds the world, the camera's path, the
// crowd's motion and the wheel odometry for every frame; Render(i) then produces frame i in any
// order. Everything is a deterministic function of SimOptions (including seed).
//
// Frames: world (z up, floor z = 0) -> base_link (x forward, y left, z up, on the floor)
// -> camera_rgb_optical_frame (x right, y down, z forward); odom coincides with base_link at
// frame 0 and drifts from the world as wheel odometry does. A handheld camera has no base_link,
// no extrinsic and no wheel odometry: has_wheel_odometry() is false and base_to_camera() empty.
#pragma once

#include <optional>
#include <vector>

#include <opencv2/core.hpp>

#include "core/common/camera.h"
#include "core/common/pose.h"
#include "core/common/time.h"
#include "core/sim/crowd.h"
#include "core/sim/handheld_motion.h"
#include "core/sim/loop_route.h"
#include "core/sim/ray_caster.h"
#include "core/sim/scene.h"
#include "core/sim/sim_options.h"
#include "core/sim/wheel_odometry.h"

namespace icgm::sim {

struct SimFrame {
  size_t index = 0;
  Time stamp;
  cv::Mat bgr;           // CV_8UC3
  cv::Mat depth_m;       // CV_32FC1 metres, NaN invalid (registered to bgr)
  cv::Mat dynamic_mask;  // CV_8UC1, 255 where a pedestrian is the visible surface
  Pose3 T_world_camera = Pose3::Identity();  // ground truth, camera_rgb_optical_frame
  // Ground truth of base_link and wheel odometry (odom -> base_link); identity and zero
  // velocities when the camera is handheld (Simulator::has_wheel_odometry() false).
  Pose3 T_world_base = Pose3::Identity();
  OdometrySample odometry;
};

struct RenderFlags {
  bool pedestrians = true;
  // false: ideal image, exact depth for every pixel (no noise, holes or range limits).
  bool sensor_effects = true;
};

class Simulator {
 public:
  // Throws LoadError when the options are inconsistent (e.g. no frames).
  explicit Simulator(const SimOptions& options);

  size_t size() const { return stamps_.size(); }
  Time stamp(size_t i) const { return stamps_[i]; }
  const Pose3& T_world_camera(size_t i) const { return T_world_camera_[i]; }
  // False for a handheld camera: no base_link, no wheel odometry, no extrinsic.
  bool has_wheel_odometry() const { return !odometry_.empty(); }
  // Only with wheel odometry (base_link's ground truth, wheel odometry odom -> base_link).
  const Pose3& T_world_base(size_t i) const { return T_world_base_.at(i); }
  const OdometrySample& odometry(size_t i) const { return odometry_.at(i); }
  // base_link's planar pose on the route; for a handheld camera, the camera's position on the
  // floor plan and its horizontal viewing direction.
  const PlanarPose& planar_pose(size_t i) const { return planar_[i]; }
  // Static extrinsic base_link -> camera_rgb_optical_frame; empty for a handheld camera.
  std::optional<Pose3> base_to_camera() const {
    return has_wheel_odometry() ? std::optional<Pose3>(T_base_camera_) : std::nullopt;
  }
  // The camera mount's extrinsic (identity for a handheld camera: prefer base_to_camera()).
  const Pose3& T_base_camera() const { return T_base_camera_; }
  const CameraIntrinsics& intrinsics() const { return options_.intrinsics; }
  const SimOptions& options() const { return options_; }
  const StaticScene& scene() const { return scene_; }
  const Crowd& crowd() const { return crowd_; }
  // The robot's loop (its options' route, unused by a handheld camera).
  const LoopRoute& route() const { return route_; }

  // Renders frame i < size(). Thread-compatible: concurrent calls on one Simulator are safe.
  SimFrame Render(size_t i, const RenderFlags& flags = RenderFlags()) const;

 private:
  static size_t NumFrames(const SimOptions& options, const LoopRoute& route);
  void BuildWheeledPath(size_t n, double dt);
  void BuildHandheldPath(size_t n, double dt);
  // The camera at t_s seconds after the first frame (between frames: interpolated on the
  // route, exact for a handheld camera).
  Pose3 CameraPoseAt(double t_s) const;

  SimOptions options_;
  LoopRoute route_;
  HandheldMotion handheld_;
  std::vector<Time> stamps_;
  std::vector<PlanarPose> planar_;
  std::vector<Pose3> T_world_camera_;
  std::vector<Pose3> T_world_base_;
  std::vector<OdometrySample> odometry_;
  Pose3 T_base_camera_;
  StaticScene scene_;
  Crowd crowd_;
  RayCaster caster_;
};

// base_link -> camera_rgb_optical_frame for a camera mount.
Pose3 CameraMountPose(const CameraMountOptions& mount);

}  // namespace icgm::sim
