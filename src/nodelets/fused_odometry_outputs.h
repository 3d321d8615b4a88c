// What the odometry fusion nodelet publishes: the fused odometry on `odom` (nav_msgs/Odometry
// with the chained covariance in the message's convention and the last step's twist,
// odometry_covariance.h) and tf odom -> child frame (REP-105; ~publish_tf, default true).
// Covariance of steps vision did not measure: ~fallback_sigma_floor_m, ~fallback_sigma_floor_rad,
// ~fallback_sigma_per_m (sigma = floor + share of the step length).
#pragma once

#include <string>

#include <ros/ros.h>
#include <tf2_ros/transform_broadcaster.h>

#include "core/odometry/fusion_queue.h"
#include "core/odometry/odometry_fusion.h"
#include "nodelets/nodelet_params.h"
#include "ros_bridge/odometry_covariance.h"

namespace icgm::nodelets {

class FusedOdometryOutputs {
 public:
  FusedOdometryOutputs(ros::NodeHandle& nh, const ros::NodeHandle& pnh, const FrameNames& frames);

  // The start pose on tf (no odom message: nothing was measured), so the first frame's pose
  // can be looked up too (the map builder's first keyframe). `child_frame`: the odometry's.
  void Start(const ros::Time& stamp, const OdometryFusion& fusion, const std::string& child_frame);
  // One fused step: odometry message + tf (+ a vision-share report every 100 frames).
  void Publish(const FusedResult& fused, const OdometryFusion& fusion);

 private:
  void PublishTf(const ros::Time& stamp, const OdometryFusion& fusion);

  ros::Publisher odom_pub_;
  tf2_ros::TransformBroadcaster tf_broadcaster_;
  FrameNames frames_;
  bool publish_tf_ = true;
  ros_bridge::FallbackStepSigmas fallback_;
  ros_bridge::OdometryCovariance covariance_;
  std::string child_frame_;  // base_frame, or the camera frame in camera-only mode
};

}  // namespace icgm::nodelets
