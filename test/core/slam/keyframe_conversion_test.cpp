#include "core/slam/keyframe_conversion.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>

namespace icgm {
namespace {

// A front-end keyframe with n keypoints: keypoint i has descriptor bytes all equal to i, a
// 3-D point unless i % 3 == 0 (no depth) and the ICGM flag when i % 2 == 0.
FrontendKeyframe MakeFrontendKeyframe(int n, bool flags) {
  FrontendKeyframe kf;
  kf.stamp = Time::FromSeconds(12.5);
  kf.odom_camera = MakePose(Vec3(0.3, -0.1, 0.2), Quat(Eigen::AngleAxisd(0.2, Vec3::UnitY())));
  kf.relative_source = MotionSource::kVision;
  kf.features.descriptors.create(n, 32, CV_8U);
  for (int i = 0; i < n; ++i) {
    kf.features.keypoints.emplace_back(cv::Point2f(10.f + i, 20.f + 2 * i), 7.f);
    kf.features.descriptors.row(i).setTo(cv::Scalar(i));
    const double nan = std::numeric_limits<double>::quiet_NaN();
    kf.points_m.push_back(i % 3 == 0 ? Vec3(nan, nan, nan) : Vec3(0.1 * i, 0.0, 1.0 + i));
    kf.robust.push_back(flags && i % 2 == 0 ? 1 : 0);
  }
  return kf;
}

TEST(KeyframeConversionTest, KeepsOnlyRobustFeaturesWithDepth) {
  const FrontendKeyframe fkf = MakeFrontendKeyframe(30, true);
  const Pose3 previous = MakePose(Vec3(0.1, 0.0, 0.0), Quat::Identity());
  const Keyframe kf = ToMapKeyframe(fkf, previous);
  // Robust (even) and with depth (not a multiple of 3): 2, 4, 8, 10, 14, ... 28.
  std::vector<int> expected;
  for (int i = 0; i < 30; ++i) {
    if (i % 2 == 0 && i % 3 != 0) expected.push_back(i);
  }
  ASSERT_EQ(kf.keypoints.size(), expected.size());
  ASSERT_EQ(kf.descriptors.rows, static_cast<int>(expected.size()));
  ASSERT_EQ(kf.points_m.size(), expected.size());
  EXPECT_TRUE(kf.binary());
  for (size_t k = 0; k < expected.size(); ++k) {
    const int i = expected[k];
    EXPECT_FLOAT_EQ(kf.keypoints[k].pt.x, 10.f + i);
    EXPECT_EQ(kf.descriptors.at<uint8_t>(static_cast<int>(k), 31), i);
    EXPECT_TRUE(kf.points_m[k].isApprox(fkf.points_m[i]));
  }
  EXPECT_TRUE(kf.relative_pose.isApprox(previous.inverse() * fkf.odom_camera, 1e-12));
  EXPECT_EQ(kf.relative_source, RelativePoseSource::kVisual);
  EXPECT_EQ(kf.stamp, fkf.stamp);
}

TEST(KeyframeConversionTest, FirstKeyframeWithoutReferenceKeepsFeaturesWithDepth) {
  const FrontendKeyframe fkf = MakeFrontendKeyframe(30, false);
  const Pose3 session_from_odom = MakePose(Vec3(1, 2, 3), Quat::Identity());
  const Keyframe kf = ToMapKeyframe(fkf, std::nullopt, session_from_odom);
  EXPECT_EQ(kf.keypoints.size(), 20u);  // 30 minus the 10 without depth
  for (const Vec3& p : kf.points_m) EXPECT_TRUE(p.allFinite());
  EXPECT_TRUE(kf.relative_pose.isApprox(session_from_odom * fkf.odom_camera, 1e-12));
  EXPECT_EQ(kf.relative_source, RelativePoseSource::kSessionStart);

  KeyframeConversionOptions strict;
  strict.keep_all_without_reference = false;
  EXPECT_TRUE(ToMapKeyframe(fkf, std::nullopt, Pose3::Identity(), strict).keypoints.empty());
}

TEST(KeyframeConversionTest, AllFeaturesWithDepthWhenNotRobustOnly) {
  KeyframeConversionOptions all;
  all.robust_only = false;
  const Keyframe kf =
      ToMapKeyframe(MakeFrontendKeyframe(30, true), Pose3::Identity(), Pose3::Identity(), all);
  EXPECT_EQ(kf.keypoints.size(), 20u);
}

TEST(KeyframeConversionTest, NonVisualStepsBecomeWheelOdometryLinks) {
  EXPECT_EQ(ToRelativePoseSource(MotionSource::kVision), RelativePoseSource::kVisual);
  EXPECT_EQ(ToRelativePoseSource(MotionSource::kWheel), RelativePoseSource::kWheelOdometry);
  EXPECT_EQ(ToRelativePoseSource(MotionSource::kConstantVelocity),
            RelativePoseSource::kWheelOdometry);
  FrontendKeyframe fkf = MakeFrontendKeyframe(6, true);
  fkf.relative_source = MotionSource::kWheel;
  EXPECT_EQ(ToMapKeyframe(fkf, Pose3::Identity()).relative_source,
            RelativePoseSource::kWheelOdometry);
}

TEST(KeyframeConversionTest, FloatDescriptorsAndMissingFlagsAreHandled) {
  FrontendKeyframe fkf = MakeFrontendKeyframe(9, true);
  fkf.features.descriptors.convertTo(fkf.features.descriptors, CV_32F);
  fkf.features.binary = false;
  fkf.robust.resize(4);  // shorter than the keypoints: the rest counts as not robust
  const Keyframe kf = ToMapKeyframe(fkf, Pose3::Identity());
  ASSERT_EQ(kf.keypoints.size(), 1u);  // only i = 2 (0 has no depth, 4+ have no flag)
  EXPECT_FALSE(kf.binary());
  EXPECT_FLOAT_EQ(kf.descriptors.at<float>(0, 0), 2.f);
}

}  // namespace
}  // namespace icgm
