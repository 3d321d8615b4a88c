// Monocular odometry (core/mono) as nav_msgs/Odometry.
//
// The pose is T_odom_camera: header.frame_id is the monocular map's frame (the camera at the
// map's first keyframe, or the last pose before a reset), child_frame_id the camera as the
// monocular odometry sees it (a frame of its own, e.g. "mono_camera", so it never gives the
// robot's camera optical frame a second tf parent).
//
// Scale state in the pose covariance (row-major, (x y z rx ry rz)):
//  - metric (wheel odometry gave the scale): position variances sigma_position_m^2;
//  - unknown (camera alone, first baseline = 1 map unit): position variances
//    kUnknownScaleVariance (1e6), i.e. "the position is not in metres: do not fuse it"; the
//    rotation is valid in both states (sigma_rotation_rad^2).
// The twist (child frame velocities over the last step) follows the same rule: linear
// variances kUnknownScaleVariance without a metric scale.
#pragma once

#include <optional>
#include <string>

#include <geometry_msgs/TransformStamped.h>
#include <nav_msgs/Odometry.h>

#include "core/common/pose.h"
#include "core/common/time.h"
#include "core/mono/mono_odometry.h"

namespace icgm::ros_bridge {

inline constexpr double kUnknownScaleVariance = 1e6;

struct MonoOdometryMsgOptions {
  std::string odom_frame = "mono_odom";
  std::string child_frame = "mono_camera";
  double sigma_position_m = 0.02;    // per axis, metric scale
  double sigma_rotation_rad = 0.02;  // per axis
};

// The previous published pose, for the twist (none: zero twist with the unknown variances).
struct MonoPreviousPose {
  Time stamp;
  Pose3 world_camera = Pose3::Identity();
};

// `result` must have a pose (result.has_pose).
nav_msgs::Odometry ToMonoOdometryMsg(const MonoFrameResult& result,
                                     const std::optional<MonoPreviousPose>& previous,
                                     const MonoOdometryMsgOptions& options);

// The message's pose as the tf transform header.frame_id -> child_frame_id at its stamp.
geometry_msgs::TransformStamped MonoOdometryTransform(const nav_msgs::Odometry& msg);

// The scale state a message carries (position variance below kUnknownScaleVariance).
bool MonoScaleKnown(const nav_msgs::Odometry& msg);

}  // namespace icgm::ros_bridge
