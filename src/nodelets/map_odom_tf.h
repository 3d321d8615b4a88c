// The map builder's tf side (REP-105): publishes map -> odom, the map's correction of the fused
// odometry, and turns rviz's "2D Pose Estimate" (the base's pose in the map) into the camera
// pose the map needs, through tf (base -> camera, odom -> camera). Owns the tf buffer the map
// builder also waits for odometry with.
#pragma once

#include <memory>
#include <string>

#include <geometry_msgs/PoseWithCovarianceStamped.h>
#include <ros/time.h>
#include <tf2_ros/buffer.h>
#include <tf2_ros/transform_broadcaster.h>
#include <tf2_ros/transform_listener.h>

#include "core/common/status.h"
#include "core/slam/slam_system.h"
#include "nodelets/nodelet_params.h"

namespace icgm::nodelets {

class MapOdomTf {
 public:
  // camera_only: the camera is the base (hand-held, no base -> camera transform).
  MapOdomTf(FrameNames frames, bool camera_only);

  tf2_ros::Buffer& buffer() { return buffer_; }
  const FrameNames& frames() const { return frames_; }

  // map -> odom, stamped 0.1 s ahead of `last_stamp` (consumers look up map -> base at the
  // latest odometry) and never twice with one stamp. Nothing while localizing without a fix:
  // the transform is unknown then, and no guess is published.
  void Publish(const SlamSystem& system, const ros::Time& last_stamp);

  // The initial pose for the localization (SlamSystem::SetInitialPose); an error with the
  // reason when it cannot be used (other frame, tf missing).
  Status SetInitialPose(const geometry_msgs::PoseWithCovarianceStamped& msg,
                        const std::string& camera_frame, SlamSystem* system) const;

 private:
  FrameNames frames_;
  bool camera_only_;
  tf2_ros::Buffer buffer_;
  tf2_ros::TransformListener listener_;
  tf2_ros::TransformBroadcaster broadcaster_;
  ros::Time last_tf_stamp_;
};

}  // namespace icgm::nodelets
