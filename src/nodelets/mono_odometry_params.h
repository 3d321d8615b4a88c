// Private parameters of the mono_odometry nodelet (launch_scripts/mono_odometry.launch).
#pragma once

#include <string>

#include <ros/node_handle.h>

#include "core/mono/mono_options.h"
#include "ros_bridge/mono_msgs.h"

namespace icgm::nodelets {

struct MonoOdometryParams {
  MonoOptions options;  // ~config_file (code defaults without), ~use_icgm overrides use_icgm
  ros_bridge::MonoOdometryMsgOptions msg;  // ~odom_frame, ~child_frame, ~sigma_*
  bool publish_tf = true;
  int queue_size = 200;             // image subscriber
  double camera_info_wait_s = 5.0;  // images held for the first camera_info, then dropped
  bool wheel_odometry = false;      // metric scale from /wheel_odom and the tf extrinsic
  int max_wait_frames = 20;         // images without a wheel message before they go on without
  std::string base_frame = "base_link";
};

// Reads the parameters; throws LoadError for a bad config file.
MonoOdometryParams ReadMonoOdometryParams(const ros::NodeHandle& pnh);

}  // namespace icgm::nodelets
