// iws09.launch with the virtual device: tf base_link -> camera_rgb_optical_frame comes from the
// URDF through robot_state_publisher and equals config/robot/iws09.yaml's mount (Kinect 1.3 m
// up, optical z along the base's x), and the pipeline publishes fused odometry while the
// (stationary) wheels report.
#include <atomic>
#include <cmath>
#include <thread>

#include <gtest/gtest.h>
#include <nav_msgs/Odometry.h>
#include <ros/ros.h>
#include <tf2_ros/transform_listener.h>

#include "core/sensor/robot_options.h"
#include "ros_bridge/conversions.h"

namespace icgm_slam::test {
namespace {

TEST(Iws09Launch, DescribesTheRobotAndPublishesOdometry) {
  ros::NodeHandle nh, pnh("~");
  std::string robot_config;
  ASSERT_TRUE(pnh.getParam("robot_config", robot_config));
  const icgm::RobotOptions robot = icgm::LoadRobotOptions(robot_config);

  // Stationary wheels at 50 Hz.
  ros::Publisher wheel_pub = nh.advertise<nav_msgs::Odometry>(robot.wheel_odom_topic, 50);
  std::atomic<bool> stop{false};
  std::thread wheels([&] {
    ros::Rate rate(50.0);
    while (!stop && ros::ok()) {
      nav_msgs::Odometry m;
      m.header.stamp = ros::Time::now();
      m.header.frame_id = "odom";
      m.child_frame_id = robot.base_frame;
      m.pose.pose.orientation.w = 1.0;
      wheel_pub.publish(m);
      rate.sleep();
    }
  });
  std::atomic<int> odoms{0};
  ros::Subscriber sub = nh.subscribe<nav_msgs::Odometry>(
      "/icgm/odom", 10, [&](const nav_msgs::OdometryConstPtr&) { ++odoms; });
  tf2_ros::Buffer buffer;
  tf2_ros::TransformListener listener(buffer);
  ros::AsyncSpinner spinner(2);
  spinner.start();

  geometry_msgs::TransformStamped t;
  std::string error;
  ASSERT_TRUE(buffer.canTransform(robot.base_frame, "camera_rgb_optical_frame", ros::Time(0),
                                  ros::Duration(30.0), &error)) << error;
  t = buffer.lookupTransform(robot.base_frame, "camera_rgb_optical_frame", ros::Time(0));
  const icgm::Pose3 mount = icgm::ros_bridge::FromTransformMsg(t.transform);
  EXPECT_NEAR(mount.translation().x(), robot.camera_x_m, 1e-6);
  EXPECT_NEAR(mount.translation().z(), robot.camera_z_m, 1e-6);
  EXPECT_NEAR(mount.translation().z(), 1.3, 1e-6);
  // Optical axis (z) along the base's forward axis, image x to the base's right.
  EXPECT_NEAR((mount.linear() * Eigen::Vector3d::UnitZ()).x(), 1.0, 1e-6);
  EXPECT_NEAR((mount.linear() * Eigen::Vector3d::UnitX()).y(), -1.0, 1e-6);

  const ros::WallTime start = ros::WallTime::now();
  while (odoms < 10 && (ros::WallTime::now() - start).toSec() < 90.0) ros::WallDuration(0.2).sleep();
  stop = true;
  wheels.join();
  EXPECT_GE(odoms.load(), 10) << "no fused odometry on /icgm/odom";
}

}  // namespace
}  // namespace icgm_slam::test
