// What the simulated robot's sensors give, under the names the pipeline and the recorded bags
// use (ros_bridge/topics.h): colour, depth and camera_info per frame; wheel odometry (/odom,
// tf odom -> base_link), /clock and the collision status every step; the base -> camera
// extrinsic on /tf_static (latched). With the scenario's planar scanner on, its scan on /scan
// (sensor_msgs/LaserScan) per frame and base -> scanner on /tf_static too. Ground truth: the
// camera pose, the walkers and the dynamic mask (only while subscribed).
#pragma once

#include <string>

#include <geometry_msgs/TransformStamped.h>
#include <ros/ros.h>

#include "core/common/pose.h"
#include "core/sim/closed_loop_simulator.h"

namespace icgm::nodelets {

struct SimFrames {
  std::string world, odom, base, camera, scanner;
};

class SimPublishers {
 public:
  // depth_encoding: "16UC1" (mm) or "32FC1" (m).
  SimPublishers(ros::NodeHandle& nh, SimFrames frames, std::string depth_encoding);
  // The scan's publisher (/scan): only when the scenario's scanner is on.
  void AdvertiseScan(ros::NodeHandle& nh);
  void PublishExtrinsic(const sim::ClosedLoopSimulator& sim);
  // The clock first (nodes on sim time), then the wheels and the status.
  void PublishStep(const sim::ClosedLoopSimulator& sim);
  void PublishFrame(const sim::ClosedLoopSimulator& sim, const sim::SimFrame& frame);

 private:
  void PublishTf(const Pose3& pose, const Time& stamp, const std::string& parent,
                 const std::string& child, const ros::Publisher& pub);
  static geometry_msgs::TransformStamped Transform(const Pose3& pose, const Time& stamp,
                                                   const std::string& parent,
                                                   const std::string& child);

  SimFrames frames_;
  std::string depth_encoding_;
  ros::Publisher clock_pub_, rgb_pub_, rgb_info_pub_, depth_pub_, depth_info_pub_, mask_pub_;
  ros::Publisher odom_pub_, tf_pub_, tf_static_pub_, gt_pub_, people_pub_, status_pub_;
  ros::Publisher scan_pub_;  // advertised with the scanner on
};

}  // namespace icgm::nodelets
