#include "ros_bridge/navigation_msgs.h"

#include <cmath>
#include <limits>
#include <vector>

#include <gtest/gtest.h>

#include "ros_bridge/conversions.h"

namespace icgm::ros_bridge {
namespace {

TEST(NavigationMsgsTest, GoalPosesThatAreNoPoseAreRefusedNamingThePart) {
  geometry_msgs::Pose pose;
  pose.position.x = 3.0;
  pose.orientation.w = 1.0;
  EXPECT_TRUE(CheckGoalPose(pose).ok());
  pose.orientation.w = 3.0;  // not normalized: a rotation all the same (move_base normalizes)
  EXPECT_TRUE(CheckGoalPose(pose).ok());
  const double nan = std::numeric_limits<double>::quiet_NaN();
  geometry_msgs::Pose bad = pose;
  bad.position.y = nan;
  Status s = CheckGoalPose(bad);
  EXPECT_FALSE(s.ok());
  EXPECT_NE(s.reason().find("goal position (3, nan, 0) is not finite"), std::string::npos)
      << s.reason();
  bad = pose;
  bad.orientation.w = 0.0;  // all-zero quaternion, a default-constructed message
  s = CheckGoalPose(bad);
  EXPECT_FALSE(s.ok());
  EXPECT_NE(s.reason().find("length about zero"), std::string::npos) << s.reason();
  bad.orientation.z = nan;
  s = CheckGoalPose(bad);
  EXPECT_FALSE(s.ok());
  EXPECT_NE(s.reason().find("not finite"), std::string::npos) << s.reason();
}

TEST(NavigationMsgsTest, TwistRoundTripCarriesOnlyTheBaseVelocities) {
  VelocityCommand cmd;
  cmd.linear_mps = 0.35;
  cmd.angular_radps = -0.8;
  geometry_msgs::Twist msg = ToTwistMsg(cmd);
  EXPECT_DOUBLE_EQ(msg.linear.x, 0.35);
  EXPECT_DOUBLE_EQ(msg.angular.z, -0.8);
  EXPECT_EQ(msg.linear.y, 0.0);
  EXPECT_EQ(msg.angular.x, 0.0);
  msg.linear.y = 5.0;  // a holonomic component the base cannot follow
  const VelocityCommand back = FromTwistMsg(msg);
  EXPECT_DOUBLE_EQ(back.linear_mps, cmd.linear_mps);
  EXPECT_DOUBLE_EQ(back.angular_radps, cmd.angular_radps);
  const VelocityCommand zero = FromTwistMsg(ToTwistMsg(VelocityCommand()));
  EXPECT_EQ(zero.linear_mps, 0.0);
  EXPECT_EQ(zero.angular_radps, 0.0);
}

TEST(NavigationMsgsTest, PathRoundTrip) {
  const std::vector<Pose3> poses = {
      MakePose({0, 0, 0}, Quat::Identity()),
      MakePose({1.5, -0.5, 0}, Quat(Eigen::AngleAxisd(0.7, Vec3::UnitZ()))),
      MakePose({2.0, 1.0, 0.1}, Quat(Eigen::AngleAxisd(-2.5, Vec3::UnitZ())))};
  const nav_msgs::Path msg = ToPathMsg(poses, "map", Time::FromSeconds(4));
  EXPECT_EQ(msg.header.frame_id, "map");
  EXPECT_EQ(FromRos(msg.header.stamp), Time::FromSeconds(4));
  ASSERT_EQ(msg.poses.size(), 3u);
  EXPECT_EQ(msg.poses[2].header.frame_id, "map");
  const std::vector<Pose3> back = FromPathMsg(msg);
  ASSERT_EQ(back.size(), poses.size());
  for (size_t i = 0; i < poses.size(); ++i) EXPECT_TRUE(back[i].isApprox(poses[i], 1e-12));
  EXPECT_TRUE(FromPathMsg(ToPathMsg({}, "map", Time())).empty());
}

TEST(NavigationMsgsTest, PlanarPathRoundTripWithHeadingsAlongThePath) {
  const std::vector<Eigen::Vector2d> points = {{0, 0}, {1, 0}, {1, 2}, {1, 2}};
  const nav_msgs::Path msg = ToPlanarPathMsg(points, "map", Time::FromSeconds(2));
  ASSERT_EQ(msg.poses.size(), 4u);
  EXPECT_EQ(msg.poses[3].header.frame_id, "map");
  // +x on the first segment, +y on the second, kept over the repeated last point.
  EXPECT_NEAR(msg.poses[0].pose.orientation.w, 1.0, 1e-12);
  EXPECT_NEAR(msg.poses[1].pose.orientation.z, std::sin(M_PI / 4), 1e-12);
  EXPECT_NEAR(msg.poses[3].pose.orientation.z, std::sin(M_PI / 4), 1e-12);
  EXPECT_EQ(msg.poses[2].pose.position.z, 0.0);
  const auto back = FromPlanarPathMsg(msg);
  ASSERT_EQ(back.size(), points.size());
  for (size_t i = 0; i < points.size(); ++i) EXPECT_EQ(back[i], points[i]) << i;
  EXPECT_TRUE(FromPlanarPathMsg(ToPlanarPathMsg({}, "map", Time())).empty());
}

TEST(NavigationMsgsTest, CircleFootprintLiesOnTheCircle) {
  const auto polygon = CircleFootprint(0.3, 16);
  ASSERT_EQ(polygon.size(), 16u);
  for (const auto& v : polygon) EXPECT_NEAR(v.norm(), 0.3, 1e-12);
  EXPECT_NEAR(polygon[4].y(), 0.3, 1e-12);  // a quarter turn
}

TEST(NavigationMsgsTest, PolygonRoundTripAtFloatPrecision) {
  const std::vector<Eigen::Vector2d> square = {
      {0.25, 0.2}, {-0.25, 0.2}, {-0.25, -0.2}, {0.25, -0.2}};
  const auto msg = ToPolygonMsg(square, "base_link", Time::FromSeconds(1));
  EXPECT_EQ(msg.header.frame_id, "base_link");
  ASSERT_EQ(msg.polygon.points.size(), 4u);
  EXPECT_FLOAT_EQ(msg.polygon.points[1].x, -0.25f);
  EXPECT_FLOAT_EQ(msg.polygon.points[1].z, 0.0f);
  const auto back = FromPolygonMsg(msg);
  ASSERT_EQ(back.size(), square.size());
  for (size_t i = 0; i < square.size(); ++i) EXPECT_TRUE(back[i].isApprox(square[i], 1e-6));
}

TEST(NavigationMsgsTest, OdometryRoundTrip) {
  OdometryData odom;
  odom.stamp = Time::FromNanoseconds(12345678901234LL);
  odom.pose = MakePose({3.0, -1.0, 0.0}, Quat(Eigen::AngleAxisd(1.1, Vec3::UnitZ())));
  odom.linear_velocity_mps = {0.4, 0.0, 0.0};
  odom.angular_velocity_rps = {0.0, 0.0, -0.3};
  const nav_msgs::Odometry msg = ToOdometryMsg(odom, "odom", "base_link");
  EXPECT_EQ(msg.header.frame_id, "odom");
  EXPECT_EQ(msg.child_frame_id, "base_link");
  EXPECT_DOUBLE_EQ(msg.twist.twist.linear.x, 0.4);
  EXPECT_DOUBLE_EQ(msg.twist.twist.angular.z, -0.3);
  const OdometryData back = FromOdometryMsg(msg);
  EXPECT_EQ(back.stamp, odom.stamp);
  EXPECT_TRUE(back.pose.isApprox(odom.pose, 1e-12));
  EXPECT_TRUE(back.linear_velocity_mps.isApprox(odom.linear_velocity_mps, 0.0));
  EXPECT_TRUE(back.angular_velocity_rps.isApprox(odom.angular_velocity_rps, 0.0));
}

TEST(NavigationMsgsTest, LaserScanRoundTrip) {
  PlanarScan scan;
  scan.stamp = Time::FromNanoseconds(1600000000123456789LL);
  scan.angle_min_rad = -M_PI;
  scan.angle_increment_rad = M_PI / 2;
  scan.range_min_m = 0.1;
  scan.range_max_m = 8.0;
  scan.ranges_m = {1.5f, std::numeric_limits<float>::infinity(), 0.25f, 7.9f};
  const sensor_msgs::LaserScan msg = ToLaserScanMsg(scan, "base_scan");
  EXPECT_EQ(msg.header.frame_id, "base_scan");
  EXPECT_FLOAT_EQ(msg.angle_max, static_cast<float>(M_PI / 2));
  const PlanarScan back = FromLaserScanMsg(msg);
  EXPECT_EQ(back.stamp, scan.stamp);
  EXPECT_EQ(back.ranges_m.size(), scan.ranges_m.size());
  EXPECT_TRUE(std::isinf(back.ranges_m[1]));
  // The same points in base_link either way (float angles: within a micrometre).
  const std::vector<Eigen::Vector3d> a = ScanPointsInBase(scan, Pose3::Identity());
  const std::vector<Eigen::Vector3d> b = ScanPointsInBase(back, Pose3::Identity());
  ASSERT_EQ(a.size(), 3u);
  ASSERT_EQ(b.size(), a.size());
  for (size_t i = 0; i < a.size(); ++i) EXPECT_TRUE(b[i].isApprox(a[i], 1e-6)) << i;
}

}  // namespace
}  // namespace icgm::ros_bridge
