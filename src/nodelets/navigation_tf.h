// The navigation nodelet's view of tf: the localized base (map -> base_link) with a flag for
// localization fixes, goals brought into the map frame, and the base -> camera extrinsic
// (waited for, never assumed: extrinsic_source.h), and base -> a planar scanner's frame the same
// way. Lookups take the latest transforms.
#pragma once

#include <optional>
#include <string>

#include <geometry_msgs/PoseStamped.h>
#include <ros/node_handle.h>
#include <tf2_ros/buffer.h>
#include <tf2_ros/transform_listener.h>
#include <Eigen/Core>

#include "core/common/pose.h"
#include "core/common/status.h"
#include "core/common/time.h"
#include "core/nav/goal_session.h"
#include "nodelets/extrinsic_source.h"

namespace icgm::nodelets {

class NavigationTf {
 public:
  // Reads the extrinsic's parameters (~extrinsic_wait_s, ...) from `pnh`.
  NavigationTf(const ros::NodeHandle& pnh, std::string map_frame, std::string odom_frame,
               std::string base_frame);

  // The latest map -> base_link and its stamp. `fix`: map -> odom differs from the previous
  // lookup's (a relocalization, loop closure or initial pose moved the map under the odometry).
  Status LocalizedBase(Pose3* T_map_base, Time* stamp, bool* fix);
  // The goal's position on the floor of the map frame (an empty frame id means the map frame)
  // and its heading there (the quaternion need not be normalized).
  Status GoalInMap(const geometry_msgs::PoseStamped& goal, Eigen::Vector2d* xy_m, double* yaw_rad);
  // LocalizedBase handed to `session` (with the fix flag); none, with the reason in *error,
  // when it is not on tf.
  std::optional<Pose3> FeedPose(GoalSession* session, std::string* error);
  // A control cycle's inputs at ros::Time::now(): the pose (fed to the session) and, while the
  // session's goal is pending, `goal`'s position in the map and the base -> camera_frame extrinsic.
  GoalCycleInputs CycleInputs(GoalSession* session, const geometry_msgs::PoseStamped& goal,
                              const std::string& camera_frame, double dt_s);
  // base -> camera_frame once known (non-blocking).
  std::optional<Pose3> Extrinsic(const std::string& camera_frame) {
    return extrinsic_.Poll(camera_frame);
  }
  // base -> scanner_frame (a planar scanner's) once known (non-blocking).
  std::optional<Pose3> ScannerExtrinsic(const std::string& scanner_frame) {
    return scanner_extrinsic_.Poll(scanner_frame);
  }

 private:
  std::string map_frame_, odom_frame_, base_frame_;
  tf2_ros::Buffer buffer_;
  tf2_ros::TransformListener listener_;
  ExtrinsicSource extrinsic_;
  ExtrinsicSource scanner_extrinsic_;
  std::optional<Pose3> last_map_odom_;
};

}  // namespace icgm::nodelets
