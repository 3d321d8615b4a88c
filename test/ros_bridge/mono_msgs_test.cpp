#include "ros_bridge/mono_msgs.h"

#include <cmath>

#include <gtest/gtest.h>

#include "ros_bridge/conversions.h"

namespace icgm::ros_bridge {
namespace {

MonoFrameResult ResultAt(double t_s, const Pose3& world_camera, bool scale_known) {
  MonoFrameResult r;
  r.stamp = Time::FromSeconds(t_s);
  r.has_pose = true;
  r.world_camera = world_camera;
  r.scale_known = scale_known;
  return r;
}

TEST(MonoMsgsTest, PoseFramesAndScaleStateInTheCovariance) {
  const Pose3 pose =
      MakePose({0.3, -1.2, 2.0}, Quat(Eigen::AngleAxisd(0.4, Vec3(0.2, 1.0, -0.3).normalized())));
  MonoOdometryMsgOptions options;
  options.odom_frame = "mono_odom";
  options.child_frame = "mono_camera";
  options.sigma_position_m = 0.05;
  options.sigma_rotation_rad = 0.01;

  const nav_msgs::Odometry unknown =
      ToMonoOdometryMsg(ResultAt(10.0, pose, false), std::nullopt, options);
  EXPECT_EQ(unknown.header.frame_id, "mono_odom");
  EXPECT_EQ(unknown.child_frame_id, "mono_camera");
  EXPECT_EQ(FromRos(unknown.header.stamp), Time::FromSeconds(10.0));
  EXPECT_TRUE(FromPoseMsg(unknown.pose.pose).isApprox(pose, 1e-12));
  EXPECT_FALSE(MonoScaleKnown(unknown));
  const geometry_msgs::TransformStamped tf = MonoOdometryTransform(unknown);
  EXPECT_EQ(tf.header.frame_id, "mono_odom");
  EXPECT_EQ(tf.child_frame_id, "mono_camera");
  EXPECT_EQ(FromRos(tf.header.stamp), Time::FromSeconds(10.0));
  EXPECT_TRUE(FromTransformMsg(tf.transform).isApprox(pose, 1e-12));
  for (int i = 0; i < 3; ++i) {
    EXPECT_EQ(unknown.pose.covariance[i * 7], kUnknownScaleVariance);
    EXPECT_NEAR(unknown.pose.covariance[(i + 3) * 7], 1e-4, 1e-12);  // rotation stays valid
  }

  const nav_msgs::Odometry metric =
      ToMonoOdometryMsg(ResultAt(10.0, pose, true), std::nullopt, options);
  EXPECT_TRUE(MonoScaleKnown(metric));
  for (int i = 0; i < 3; ++i) EXPECT_NEAR(metric.pose.covariance[i * 7], 0.0025, 1e-12);
  EXPECT_EQ(metric.pose.covariance[1], 0.0);  // no correlations claimed
}

// A camera turning about its own y axis while moving along its z axis: the twist is in the
// child (camera) frame.
TEST(MonoMsgsTest, TwistOfTheLastStepInTheChildFrame) {
  const Pose3 start = MakePose({1, 2, 3}, Quat(Eigen::AngleAxisd(1.0, Vec3::UnitZ())));
  const Pose3 step = MakePose({0, 0, 0.1}, Quat(Eigen::AngleAxisd(0.05, Vec3::UnitY())));
  const MonoPreviousPose previous{Time::FromSeconds(5.0), start};
  const nav_msgs::Odometry msg =
      ToMonoOdometryMsg(ResultAt(5.5, start * step, true), previous, MonoOdometryMsgOptions{});
  // Translation of the step expressed in the new camera axes, over 0.5 s.
  const Vec3 expected = step.linear().transpose() * Vec3(0, 0, 0.2);
  EXPECT_NEAR(msg.twist.twist.linear.x, expected.x(), 1e-9);
  EXPECT_NEAR(msg.twist.twist.linear.y, expected.y(), 1e-9);
  EXPECT_NEAR(msg.twist.twist.linear.z, expected.z(), 1e-9);
  EXPECT_NEAR(msg.twist.twist.angular.x, 0.0, 1e-9);
  EXPECT_NEAR(msg.twist.twist.angular.y, 0.1, 1e-9);
  EXPECT_NEAR(msg.twist.twist.angular.z, 0.0, 1e-9);
  EXPECT_LT(msg.twist.covariance[0], kUnknownScaleVariance);

  // Unknown scale: the linear twist is in map units, flagged like the position.
  const nav_msgs::Odometry unscaled =
      ToMonoOdometryMsg(ResultAt(5.5, start * step, false), previous, MonoOdometryMsgOptions{});
  EXPECT_EQ(unscaled.twist.covariance[0], kUnknownScaleVariance);
  EXPECT_LT(unscaled.twist.covariance[35], kUnknownScaleVariance);
}

}  // namespace
}  // namespace icgm::ros_bridge
