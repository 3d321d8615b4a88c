// One navigation goal's life as a move_base-style action server runs it, ROS-free: the learned
// map (loaded from a file; a load failure is the reason every goal is aborted with until a load
// succeeds), a goal that waits for the localized pose, its own position in the map frame and the
// base -> camera extrinsic (at most pose_wait_s, then aborted with what was missing), the
// Navigator driving it, and the outcome with the text an action result carries.
//
// Use (the navigation nodelet): LoadMap once and on reload; Accept(wall_s) for each new goal;
// each control cycle Cycle(inputs) -> publish its command, end the goal on kSucceeded /
// kAborted; Cancel on preemption. UpdatePose / UpdateDepth feed the Navigator as the sensors
// arrive. Not thread-safe (the nodelet's callbacks share one queue).
#pragma once

#include <optional>
#include <string>

#include <Eigen/Core>

#include "core/common/pose.h"
#include "core/common/status.h"
#include "core/common/time.h"
#include "core/common/velocity_command.h"
#include "core/map/hybrid_map.h"
#include "core/nav/navigation_options.h"
#include "core/nav/navigator.h"

namespace icgm {

// What one control cycle's caller learns.
struct GoalCycleInputs {
  Time now;                        // the control cycle's time (sensor clock)
  double dt_s = 0.1;               // its length
  double wall_s = 0.0;             // wall clock (s), for the pose wait
  std::optional<Pose3> T_map_base;  // the localized base, or none (pose_error says why)
  std::string pose_error;
  // Only read while the goal is pending: the goal's position on the map frame's floor, or why it
  // is not known (e.g. its frame is not on tf), and the base -> camera extrinsic.
  Status goal_status = Status::Error("goal position unknown");
  Eigen::Vector2d goal_m = Eigen::Vector2d::Zero();
  // Its heading in the map frame (navigator.goal_yaw_tolerance_rad); none: ignored.
  std::optional<double> goal_yaw_rad;
  std::optional<Pose3> T_base_camera;
  std::string extrinsic_error = "no base -> camera extrinsic";
};

enum class GoalCycleResult {
  kIdle,       // no goal
  kWaiting,    // pending: pose, goal frame or extrinsic not there yet (`text` says which)
  kStarted,    // the route was planned this cycle (Navigator::route() is new)
  kDriving,    // command to the base
  kSucceeded,  // goal reached (`text`: how close); zero command, the goal is over
  kAborted,    // given up (`text`: why); zero command, the goal is over
};

struct GoalCycle {
  GoalCycleResult result = GoalCycleResult::kIdle;
  std::string text;
  VelocityCommand command;  // zero unless kDriving
};

class GoalSession {
 public:
  explicit GoalSession(NavigationOptions options = NavigationOptions(), double pose_wait_s = 5.0);

  // Loads the learned map at `path` (an empty path, a missing, corrupt or empty map fail with
  // the reason, which then aborts every goal until a load succeeds). Ends any goal.
  Status LoadMap(const std::string& path);
  bool has_map() const { return map_error_.empty(); }
  // After a successful LoadMap: a note on the file's format (map_store.h's LoadMap), else empty.
  const std::string& map_note() const { return map_note_; }
  const HybridMap& map() const { return map_; }

  // A new goal received at wall time wall_s (preempting any other). Fails with the map error
  // at once when there is no map (the goal is then over).
  Status Accept(double wall_s);
  // Ends the goal (cancel, preemption): zero command from now on.
  void Cancel();
  bool active() const { return pending_ || driving_; }
  bool pending() const { return pending_; }

  void UpdatePose(Time stamp, const Pose3& T_map_base, bool fix) {
    navigator_.UpdatePose(stamp, T_map_base, fix);
  }
  Status UpdateDepth(Time stamp, const cv::Mat& depth_m, const CameraIntrinsics& intrinsics,
                     const Pose3& T_base_camera) {
    return navigator_.UpdateDepth(stamp, depth_m, intrinsics, T_base_camera);
  }
  // A planar scan for the next depth image (Navigator::UpdateScan).
  void UpdateScan(const PlanarScan& scan, const Pose3& T_base_scanner) {
    navigator_.UpdateScan(scan, T_base_scanner);
  }

  // One control cycle (see GoalCycleResult). Never throws.
  GoalCycle Cycle(const GoalCycleInputs& in);

  const Navigator& navigator() const { return navigator_; }

 private:
  GoalCycle Start(const GoalCycleInputs& in);
  GoalCycle End(GoalCycleResult result, std::string text);

  Navigator navigator_;
  double pose_wait_s_;
  HybridMap map_;
  std::string map_error_ = "no map loaded";
  std::string map_note_;
  bool map_set_ = false;  // the Navigator has the map (needs the extrinsic, known at a goal)
  bool pending_ = false, driving_ = false;
  double received_wall_s_ = 0.0;
};

}  // namespace icgm
