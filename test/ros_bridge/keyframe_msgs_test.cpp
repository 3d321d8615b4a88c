#include "ros_bridge/keyframe_msgs.h"

#include <cmath>
#include <limits>

#include <gtest/gtest.h>

#include "core/odometry/odometry_fusion.h"
#include "ros_bridge/conversions.h"

namespace icgm::ros_bridge {
namespace {

FrontendKeyframe MakeKeyframe() {
  FrontendKeyframe k;
  k.id = 7;
  k.frame_index = 42;
  k.stamp = Time::FromSeconds(3.25);
  k.odom_camera = MakePose({1.0, -0.5, 0.2}, Quat(Eigen::AngleAxisd(0.3, Vec3::UnitY())));
  k.odom_base = MakePose({1.1, -0.4, 0.0}, Quat(Eigen::AngleAxisd(0.3, Vec3::UnitZ())));
  k.relative_pose = MakePose({0.2, 0.0, 0.01}, Quat(Eigen::AngleAxisd(0.02, Vec3::UnitX())));
  k.relative_source = MotionSource::kVision;
  Mat6 c = Mat6::Identity() * 1e-4;
  c(1, 4) = c(4, 1) = 3e-6;
  k.covariance = c;
  k.wheel_camera_motion = MakePose({0.21, 0.0, 0.0}, Quat::Identity());
  for (int i = 0; i < 4; ++i) {
    k.features.keypoints.emplace_back(10.f * i + 0.25f, 5.f + i, 7.f, 15.f * i, 0.5f, i % 2);
    k.robust.push_back(i % 2);
    k.points_m.emplace_back(0.1 * i, -0.2, 1.5 + 0.01 * i);
  }
  k.points_m[2].setConstant(std::numeric_limits<double>::quiet_NaN());  // no depth
  k.features.binary = true;
  k.features.descriptors = cv::Mat(4, 32, CV_8U);
  cv::randu(k.features.descriptors, 0, 255);
  k.depth_m = cv::Mat(6, 8, CV_32F, cv::Scalar(2.5f));
  k.depth_m.at<float>(1, 2) = std::numeric_limits<float>::quiet_NaN();
  k.bgr = cv::Mat(6, 8, CV_8UC3, cv::Scalar(10, 20, 30));
  return k;
}

TEST(KeyframeMsgsTest, RoundTripKeepsWhatTheMapUses) {
  const FrontendKeyframe k = MakeKeyframe();
  sensor_msgs::CameraInfo info;
  info.width = 8;
  info.height = 6;
  const icgm_slam::Keyframe msg = ToKeyframeMsg(k, "camera_rgb_optical_frame", info);
  EXPECT_EQ(msg.header.frame_id, "camera_rgb_optical_frame");
  EXPECT_EQ(msg.camera_info.width, 8u);
  FrontendKeyframe back;
  ASSERT_TRUE(FromKeyframeMsg(msg, &back).ok());
  EXPECT_EQ(back.id, 7u);
  EXPECT_EQ(back.frame_index, 42u);
  EXPECT_EQ(back.stamp, k.stamp);
  EXPECT_TRUE(back.odom_camera.isApprox(k.odom_camera, 1e-12));
  EXPECT_TRUE(back.odom_base.isApprox(k.odom_base, 1e-12));
  EXPECT_TRUE(back.relative_pose.isApprox(k.relative_pose, 1e-12));
  EXPECT_EQ(back.relative_source, MotionSource::kVision);
  ASSERT_TRUE(back.covariance.has_value());
  EXPECT_EQ((*back.covariance - *k.covariance).norm(), 0.0);
  ASSERT_TRUE(back.wheel_camera_motion.has_value());
  EXPECT_TRUE(back.wheel_camera_motion->isApprox(*k.wheel_camera_motion, 1e-12));
  EXPECT_EQ(back.robust, k.robust);
  ASSERT_EQ(back.features.keypoints.size(), 4u);
  EXPECT_FLOAT_EQ(back.features.keypoints[3].pt.x, 30.25f);
  EXPECT_EQ(cv::norm(back.features.descriptors, k.features.descriptors, cv::NORM_INF), 0.0);
  ASSERT_EQ(back.points_m.size(), 4u);
  EXPECT_EQ(back.points_m[3], k.points_m[3]);
  EXPECT_FALSE(back.points_m[2].allFinite());
  ASSERT_EQ(back.depth_m.type(), CV_32FC1);
  EXPECT_FLOAT_EQ(back.depth_m.at<float>(0, 0), 2.5f);
  EXPECT_FALSE(std::isfinite(back.depth_m.at<float>(1, 2)));
  ASSERT_EQ(back.bgr.type(), CV_8UC3);
  EXPECT_EQ(back.bgr.at<cv::Vec3b>(5, 7), cv::Vec3b(10, 20, 30));
}

TEST(KeyframeMsgsTest, FirstKeyframeWithoutCovarianceOrWheelsOrImage) {
  FrontendKeyframe k = MakeKeyframe();
  k.relative_source = MotionSource::kNone;
  k.covariance.reset();
  k.wheel_camera_motion.reset();
  k.bgr = cv::Mat();
  FrontendKeyframe back;
  ASSERT_TRUE(FromKeyframeMsg(ToKeyframeMsg(k, "cam", sensor_msgs::CameraInfo()), &back).ok());
  EXPECT_EQ(back.relative_source, MotionSource::kNone);
  EXPECT_FALSE(back.covariance.has_value());
  EXPECT_FALSE(back.wheel_camera_motion.has_value());
  EXPECT_TRUE(back.bgr.empty());
}

TEST(KeyframeMsgsTest, RefusesInconsistentSizes) {
  icgm_slam::Keyframe msg = ToKeyframeMsg(MakeKeyframe(), "cam", sensor_msgs::CameraInfo());
  FrontendKeyframe back;
  msg.points_m.pop_back();
  EXPECT_FALSE(FromKeyframeMsg(msg, &back).ok());
  msg = ToKeyframeMsg(MakeKeyframe(), "cam", sensor_msgs::CameraInfo());
  msg.features.robust.pop_back();
  EXPECT_FALSE(FromKeyframeMsg(msg, &back).ok());
  msg = ToKeyframeMsg(MakeKeyframe(), "cam", sensor_msgs::CameraInfo());
  msg.relative_source = 9;
  EXPECT_FALSE(FromKeyframeMsg(msg, &back).ok());
}

}  // namespace
}  // namespace icgm::ros_bridge
