// Test helper: replays a bag's sensor topics into running nodelets in lock step (publish one
// RGB-D frame, wait until the pipeline has answered), so rostests are deterministic and never
// drop frames, whatever the machine's load.
#pragma once

#include <functional>
#include <string>
#include <vector>

#include <ros/ros.h>

#include "core/common/pose.h"

namespace icgm_slam::test {

struct ReplayOptions {
  std::string bag_path;
  int max_frames = 0;            // 0: all
  double answer_timeout_s = 10;  // per frame
  // Camera topics only (no wheel odometry, no /tf_static): a hand-held camera.
  bool camera_only = false;
  // Everything but /tf_static (the extrinsic).
  bool no_tf_static = false;
  // Frames of the bag skipped before the replay (with their wheel odometry).
  int first_frame = 0;
  // Wheel odometry published as odom_offset * T_odom_base: odometry restarted elsewhere.
  icgm::Pose3 odom_offset = icgm::Pose3::Identity();
};

// `answered(i)` must return true once the pipeline has processed frame i (0-based); called
// while spinning. Returns the number of frames replayed; fails the current gtest on timeouts.
int ReplayBag(ros::NodeHandle& nh, const ReplayOptions& options,
              const std::function<bool(int frame_index)>& answered);

// Waits until every topic in `topics` has at least one subscriber.
bool WaitForSubscribers(const std::vector<ros::Publisher>& pubs, double timeout_s);

}  // namespace icgm_slam::test
