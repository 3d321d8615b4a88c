// Frames replayed without /tf_static: the registration and fusion nodelets must hold them (no
// relative pose, no odometry guessed with an identity extrinsic); once the bag's /tf_static is
// published every held frame is processed and the fused base pose uses the real extrinsic.
#include <cstdio>

#include <gtest/gtest.h>
#include <icgm_slam/RegistrationResult.h>
#include <nav_msgs/Odometry.h>
#include <rosbag/bag.h>
#include <rosbag/view.h>
#include <tf2_msgs/TFMessage.h>
#include <tf2_ros/static_transform_broadcaster.h>

#include "bag_replayer.h"
#include "ros_bridge/bag_reader.h"
#include "ros_bridge/conversions.h"
#include "ros_bridge/topics.h"

namespace icgm_slam::test {
namespace {

void SpinFor(double seconds) {
  const ros::WallTime end = ros::WallTime::now() + ros::WallDuration(seconds);
  while (ros::ok() && ros::WallTime::now() < end) {
    ros::spinOnce();
    ros::WallDuration(0.02).sleep();
  }
}

TEST(ExtrinsicWait, FramesAreHeldUntilTheTransformArrives) {
  ros::NodeHandle nh;
  ros::NodeHandle pnh("~");
  ReplayOptions options;
  ASSERT_TRUE(pnh.getParam("bag", options.bag_path));
  options.max_frames = 20;
  options.no_tf_static = true;
  const int delay = 1;  // registration needs a reference (features come without delay)

  std::vector<icgm_slam::RegistrationResult::ConstPtr> relative;
  std::vector<nav_msgs::Odometry::ConstPtr> odom;
  ros::Subscriber relative_sub = nh.subscribe<icgm_slam::RegistrationResult>(
      "/icgm/relative_pose", 100,
      [&](const icgm_slam::RegistrationResult::ConstPtr& m) { relative.push_back(m); });
  ros::Subscriber odom_sub = nh.subscribe<nav_msgs::Odometry>(
      "/icgm/odom", 100, [&](const nav_msgs::Odometry::ConstPtr& m) { odom.push_back(m); });

  // Paced, not lock-step: the pipeline is expected not to answer.
  const int frames = ReplayBag(nh, options, [](int) {
    SpinFor(0.15);
    return true;
  });
  ASSERT_EQ(frames, options.max_frames);
  SpinFor(1.5);
  EXPECT_EQ(relative.size(), 0u) << "registered without the extrinsic";
  EXPECT_EQ(odom.size(), 0u) << "odometry guessed without the extrinsic";

  // The bag's /tf_static now: the held frames go through.
  rosbag::Bag bag(options.bag_path, rosbag::bagmode::Read);
  tf2_ros::StaticTransformBroadcaster static_tf;
  for (const rosbag::MessageInstance& m :
       rosbag::View(bag, rosbag::TopicQuery(std::string(icgm::ros_bridge::topics::kTfStatic)))) {
    if (auto tf = m.instantiate<tf2_msgs::TFMessage>()) static_tf.sendTransform(tf->transforms);
  }
  const ros::WallTime end = ros::WallTime::now() + ros::WallDuration(15.0);
  while (ros::ok() && ros::WallTime::now() < end &&
         static_cast<int>(odom.size()) < frames - delay) {
    SpinFor(0.05);
  }
  SpinFor(0.5);
  std::printf("after /tf_static: %zu relative poses, %zu fused poses for %d frames\n",
              relative.size(), odom.size(), frames);
  EXPECT_EQ(static_cast<int>(relative.size()), frames - delay);
  EXPECT_EQ(static_cast<int>(odom.size()), frames - delay);
  ASSERT_FALSE(odom.empty());
  EXPECT_EQ(odom.back()->child_frame_id, icgm::ros_bridge::topics::kBaseFrame);

  // With the real extrinsic the base moves like the ground truth's base.
  icgm::ros_bridge::BagReader reader(options.bag_path);
  icgm::ros_bridge::RgbdBagStream stream(reader, icgm::ros_bridge::RgbdBagTopics{});
  ASSERT_TRUE(stream.base_to_camera().has_value());
  const icgm::Pose3 camera_to_base = stream.base_to_camera()->inverse();
  const auto gt_first = icgm::PoseAt(
      stream.ground_truth(), icgm::ros_bridge::FromRos(odom.front()->header.stamp), 0.01);
  const auto gt_last = icgm::PoseAt(
      stream.ground_truth(), icgm::ros_bridge::FromRos(odom.back()->header.stamp), 0.01);
  ASSERT_TRUE(gt_first && gt_last);
  const icgm::Pose3 truth = icgm::Between(*gt_first * camera_to_base, *gt_last * camera_to_base);
  const icgm::Pose3 est = icgm::Between(icgm::ros_bridge::FromPoseMsg(odom.front()->pose.pose),
                                        icgm::ros_bridge::FromPoseMsg(odom.back()->pose.pose));
  std::printf("base moved %.3f m, estimate off by %.4f m\n", truth.translation().norm(),
              (truth.translation() - est.translation()).norm());
  EXPECT_GT(truth.translation().norm(), 0.1);
  EXPECT_LT((truth.translation() - est.translation()).norm(), 0.02);
}

}  // namespace
}  // namespace icgm_slam::test
