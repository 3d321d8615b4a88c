#include "nodelets/sim_publishers.h"

#include <geometry_msgs/PoseArray.h>
#include <geometry_msgs/PoseStamped.h>
#include <nav_msgs/Odometry.h>
#include <rosgraph_msgs/Clock.h>
#include <sensor_msgs/CameraInfo.h>
#include <sensor_msgs/Image.h>
#include <sensor_msgs/LaserScan.h>
#include <tf2_msgs/TFMessage.h>

#include <icgm_slam/SimStatus.h>

#include "core/sim/sim_export.h"
#include "ros_bridge/conversions.h"
#include "ros_bridge/navigation_msgs.h"
#include "ros_bridge/sim_msgs.h"
#include "ros_bridge/topics.h"

namespace icgm::nodelets {

namespace topics = ros_bridge::topics;

SimPublishers::SimPublishers(ros::NodeHandle& nh, SimFrames frames, std::string depth_encoding)
    : frames_(std::move(frames)), depth_encoding_(std::move(depth_encoding)) {
  clock_pub_ = nh.advertise<rosgraph_msgs::Clock>("/clock", 10);
  rgb_pub_ = nh.advertise<sensor_msgs::Image>(topics::kRgbImage, 5);
  rgb_info_pub_ = nh.advertise<sensor_msgs::CameraInfo>(topics::kRgbInfo, 5);
  depth_pub_ = nh.advertise<sensor_msgs::Image>(
      depth_encoding_ == "16UC1" ? topics::kDepthImageMm : topics::kDepthImageM, 5);
  depth_info_pub_ = nh.advertise<sensor_msgs::CameraInfo>(topics::kDepthInfo, 5);
  mask_pub_ = nh.advertise<sensor_msgs::Image>(topics::kDynamicMask, 5);
  odom_pub_ = nh.advertise<nav_msgs::Odometry>(topics::kWheelOdom, 50);
  tf_pub_ = nh.advertise<tf2_msgs::TFMessage>(topics::kTf, 50);
  tf_static_pub_ = nh.advertise<tf2_msgs::TFMessage>(topics::kTfStatic, 1, true);
  gt_pub_ = nh.advertise<geometry_msgs::PoseStamped>(topics::kGroundTruthPose, 10);
  people_pub_ = nh.advertise<geometry_msgs::PoseArray>("/ground_truth/people", 5);
  status_pub_ = nh.advertise<icgm_slam::SimStatus>("sim/status", 50);
}

void SimPublishers::AdvertiseScan(ros::NodeHandle& nh) {
  scan_pub_ = nh.advertise<sensor_msgs::LaserScan>(topics::kScan, 5);
}

void SimPublishers::PublishExtrinsic(const sim::ClosedLoopSimulator& sim) {
  // One latched message with every static transform (a latched topic keeps the last only).
  tf2_msgs::TFMessage m;
  m.transforms.push_back(Transform(sim.T_base_camera(), sim.stamp(), frames_.base, frames_.camera));
  if (sim.options().scanner.enabled) {
    m.transforms.push_back(
        Transform(sim.T_base_scanner(), sim.stamp(), frames_.base, frames_.scanner));
  }
  tf_static_pub_.publish(m);
}

void SimPublishers::PublishStep(const sim::ClosedLoopSimulator& sim) {
  rosgraph_msgs::Clock clock;
  clock.clock = ros_bridge::ToRos(sim.stamp());
  clock_pub_.publish(clock);
  ros_bridge::OdometryData odom;
  odom.stamp = sim.stamp();
  odom.pose = sim.odometry().T_odom_base;
  odom.linear_velocity_mps = sim.odometry().linear_velocity_mps;
  odom.angular_velocity_rps = sim.odometry().angular_velocity_rps;
  odom_pub_.publish(ros_bridge::ToOdometryMsg(odom, frames_.odom, frames_.base));
  PublishTf(odom.pose, sim.stamp(), frames_.odom, frames_.base, tf_pub_);
  status_pub_.publish(ros_bridge::ToSimStatusMsg(sim, frames_.world));
}

void SimPublishers::PublishFrame(const sim::ClosedLoopSimulator& sim, const sim::SimFrame& f) {
  namespace rb = ros_bridge;
  const CameraIntrinsics& k = sim.intrinsics();
  const std::string& camera = frames_.camera;
  rgb_pub_.publish(rb::ToImageMsg(f.bgr, "bgr8", camera, f.stamp));
  rgb_info_pub_.publish(rb::ToCameraInfo(k, camera, f.stamp));
  if (depth_encoding_ == "16UC1") {
    depth_pub_.publish(
        rb::ToImageMsg(sim::DepthToMillimetres(f.depth_m), "16UC1", camera, f.stamp));
  } else {
    depth_pub_.publish(rb::ToImageMsg(f.depth_m, "32FC1", camera, f.stamp));
  }
  depth_info_pub_.publish(rb::ToCameraInfo(k, camera, f.stamp));
  if (mask_pub_.getNumSubscribers() > 0) {
    mask_pub_.publish(rb::ToImageMsg(f.dynamic_mask, "mono8", camera, f.stamp));
  }
  geometry_msgs::PoseStamped gt;
  gt.header.stamp = rb::ToRos(f.stamp);
  gt.header.frame_id = frames_.world;
  gt.pose = rb::ToPoseMsg(f.T_world_camera);
  gt_pub_.publish(gt);
  people_pub_.publish(rb::ToPeopleMsg(sim.pedestrians(), frames_.world, f.stamp));
  if (scan_pub_) scan_pub_.publish(rb::ToLaserScanMsg(sim.RenderScan(), frames_.scanner));
}

geometry_msgs::TransformStamped SimPublishers::Transform(const Pose3& pose, const Time& stamp,
                                                         const std::string& parent,
                                                         const std::string& child) {
  geometry_msgs::TransformStamped t;
  t.header.stamp = ros_bridge::ToRos(stamp);
  t.header.frame_id = parent;
  t.child_frame_id = child;
  t.transform = ros_bridge::ToTransformMsg(pose);
  return t;
}

void SimPublishers::PublishTf(const Pose3& pose, const Time& stamp, const std::string& parent,
                              const std::string& child, const ros::Publisher& pub) {
  tf2_msgs::TFMessage m;
  m.transforms.push_back(Transform(pose, stamp, parent, child));
  pub.publish(m);
}

}  // namespace icgm::nodelets
