#include "core/odometry/odometry_fusion.h"

#include <gtest/gtest.h>

#include <cmath>

#include "../registration/synthetic_rgbd.h"
#include "core/common/option_reader.h"
#include "core/registration/rgbd_registration.h"

namespace icgm {
namespace {

Time Sec(double s) { return Time::FromNanoseconds(static_cast<int64_t>(std::llround(s * 1e9))); }

Pose3 Planar(double x, double y, double yaw_deg) {
  return MakePose(Vec3(x, y, 0.0), Quat(Eigen::AngleAxisd(yaw_deg * M_PI / 180.0, Vec3::UnitZ())));
}

// Camera 1.3 m above the base, 0.2 m forward, optical axis along the base's x axis.
FusionOptions RobotFusion() {
  FusionOptions o;
  ReadOptions(OptionReader::FromString("base_to_camera_x_m: 0.2\n"
                                       "base_to_camera_z_m: 1.3\n"
                                       "base_to_camera_roll_deg: -90\n"
                                       "base_to_camera_yaw_deg: -90\n"),
              &o);
  return o;
}

TEST(OdometryFusionTest, ExtrinsicFromRollPitchYaw) {
  const FusionOptions o = RobotFusion();
  // Camera optical z (forward) is base x, optical x (right) is base -y, optical y (down) base -z.
  EXPECT_TRUE((o.base_to_camera.linear() * Vec3::UnitZ()).isApprox(Vec3::UnitX(), 1e-12));
  EXPECT_TRUE((o.base_to_camera.linear() * Vec3::UnitX()).isApprox(-Vec3::UnitY(), 1e-12));
  EXPECT_TRUE((o.base_to_camera.linear() * Vec3::UnitY()).isApprox(-Vec3::UnitZ(), 1e-12));
  EXPECT_TRUE(o.base_to_camera.translation().isApprox(Vec3(0.2, 0, 1.3)));
}

TEST(OdometryFusionTest, FallsBackToWheelOdometryWhenDepthIsAllZero) {
  // Vision: a registration attempt on an all-zero depth image must fail...
  const CameraIntrinsics k = test::TumLikeCamera();
  const cv::Mat depth_ref = test::RenderRoomDepth(Pose3::Identity(), k);
  const cv::Mat zero = cv::Mat::zeros(k.height_px, k.width_px, CV_32FC1);
  std::vector<cv::Point2f> pts;
  for (int i = 0; i < 50; ++i) pts.emplace_back(50.f + 10.f * i, 100.f + 5.f * i);
  const RegistrationResult reg = RegisterRgbd(pts, depth_ref, pts, zero, k, RegistrationOptions());
  ASSERT_FALSE(reg.status.ok());
  EXPECT_EQ(reg.depth_rejects.missing, 50u);

  // ...so the fused pose follows the wheel odometry through the extrinsic.
  WheelOdometryBuffer wheel;
  for (int i = 0; i <= 20; ++i) {
    ASSERT_TRUE(wheel.Add(Sec(0.05 * i), Planar(0.5 * 0.05 * i, 0, 10.0 * 0.05 * i)).ok());
  }
  OdometryFusion fusion(RobotFusion());
  fusion.Update(Sec(0.1), nullptr, &wheel);
  EXPECT_TRUE(fusion.odom_base().isApprox(Planar(0.05, 0, 1.0), 1e-9));
  const FusionStep step =
      fusion.Update(Sec(0.6), reg.status.ok() ? &reg.relative_pose : nullptr, &wheel);
  EXPECT_EQ(step.source, MotionSource::kWheel);
  EXPECT_TRUE(fusion.odom_base().isApprox(Planar(0.3, 0, 6.0), 1e-9));
  // The camera moved mostly along its optical axis (the robot drove forward).
  const Vec3 t = step.camera_prev_cur.translation();
  EXPECT_GT(t.z(), 0.24);
  EXPECT_NEAR(t.y(), 0.0, 1e-9);  // planar motion: no vertical motion of the camera
  EXPECT_EQ(fusion.stats().frames[static_cast<size_t>(MotionSource::kWheel)], 1u);
  EXPECT_EQ(fusion.stats().VisionShareByFrames(), 0.0);
}

TEST(OdometryFusionTest, VisionPreferredAndSharesCounted) {
  // Without the vision/wheel gate (the thesis's fusion): vision whenever registration succeeds.
  FusionOptions thesis;
  thesis.max_vision_wheel_disagreement_m = 0.0;
  thesis.max_vision_wheel_disagreement_deg = 0.0;
  OdometryFusion fusion(thesis);
  WheelOdometryBuffer wheel;
  for (int i = 0; i <= 10; ++i) ASSERT_TRUE(wheel.Add(Sec(0.1 * i), Planar(0.2 * i, 0, 0)).ok());
  fusion.Update(Sec(0.0), nullptr, &wheel);
  const Pose3 step_vis = MakePose(Vec3(0.0, 0.0, 0.1), Quat::Identity());
  for (int i = 1; i <= 3; ++i) {
    EXPECT_EQ(fusion.Update(Sec(0.1 * i), &step_vis, &wheel).source, MotionSource::kVision);
  }
  EXPECT_EQ(fusion.Update(Sec(0.4), nullptr, &wheel).source, MotionSource::kWheel);
  const FusionStats& s = fusion.stats();
  EXPECT_EQ(s.total_frames(), 4u);
  EXPECT_DOUBLE_EQ(s.VisionShareByFrames(), 0.75);
  EXPECT_NEAR(s.VisionShareByDistance(), 0.3 / 0.5, 1e-9);  // the wheel step was 0.2 m
  // Identity extrinsic: camera = base; 3 x 0.1 m in z from vision, then 0.2 m in x.
  EXPECT_TRUE(fusion.odom_camera().translation().isApprox(Vec3(0.2, 0.0, 0.3), 1e-9));
}

TEST(OdometryFusionTest, VisualStepThatDisagreesWithTheWheelsIsOverruled) {
  FusionOptions o = RobotFusion();
  o.max_vision_wheel_disagreement_m = 0.03;
  o.max_vision_wheel_disagreement_deg = 1.5;
  WheelOdometryBuffer wheel;
  // The base drives straight at 0.5 m/s, sampled at 20 Hz.
  for (int i = 0; i <= 40; ++i) ASSERT_TRUE(wheel.Add(Sec(0.05 * i), Planar(0.025 * i, 0, 0)).ok());
  OdometryFusion fusion(o);
  fusion.Initialize(Sec(0.0), &wheel);
  const Pose3 c = o.base_to_camera;
  // True camera step over 0.1 s: 5 cm forward, in the camera frame.
  const Pose3 truth = c.inverse() * Planar(0.05, 0, 0) * c;
  // A good visual step (1 cm off) is kept.
  const Pose3 good = truth * MakePose(Vec3(0.01, 0, 0), Quat::Identity());
  FusionStep step = fusion.Update(Sec(0.1), &good, &wheel);
  EXPECT_EQ(step.source, MotionSource::kVision);
  EXPECT_TRUE(step.vision_rejected.ok());
  EXPECT_TRUE(step.camera_prev_cur.isApprox(good, 1e-12));
  // A step that followed a walker (20 cm sideways) is replaced by the wheel motion, with a reason.
  const Pose3 walker = truth * MakePose(Vec3(0.2, 0, 0), Quat::Identity());
  step = fusion.Update(Sec(0.2), &walker, &wheel);
  EXPECT_EQ(step.source, MotionSource::kWheel);
  EXPECT_FALSE(step.vision_rejected.ok());
  EXPECT_NE(step.vision_rejected.reason().find("disagrees"), std::string::npos);
  EXPECT_LT((step.camera_prev_cur.translation() - truth.translation()).norm(), 1e-6);
  // A rotation beyond the angular bound is overruled too.
  const Pose3 turned =
      truth * MakePose(Vec3::Zero(), Quat(Eigen::AngleAxisd(3.0 * M_PI / 180.0, Vec3::UnitY())));
  EXPECT_EQ(fusion.Update(Sec(0.3), &turned, &wheel).source, MotionSource::kWheel);
  // Without wheel data covering the span, vision is used as before.
  const Pose3 far = truth * MakePose(Vec3(0.2, 0, 0), Quat::Identity());
  EXPECT_EQ(fusion.Update(Sec(5.0), &far, &wheel).source, MotionSource::kVision);
}

TEST(OdometryFusionTest, ConstantVelocityThenStop) {
  FusionOptions o;
  o.max_constant_velocity_s = 0.25;
  OdometryFusion fusion(o);
  fusion.Update(Sec(0.0), nullptr, nullptr);
  const Pose3 step = MakePose(Vec3(0.1, 0, 0), Quat::Identity());
  fusion.Update(Sec(0.1), &step, nullptr);  // 1 m/s
  FusionStep s1 = fusion.Update(Sec(0.2), nullptr, nullptr);
  EXPECT_EQ(s1.source, MotionSource::kConstantVelocity);
  EXPECT_NEAR(s1.camera_prev_cur.translation().x(), 0.1, 1e-12);
  EXPECT_FALSE(s1.wheel_status.ok());
  EXPECT_EQ(fusion.Update(Sec(0.3), nullptr, nullptr).source, MotionSource::kConstantVelocity);
  const FusionStep s3 = fusion.Update(Sec(0.4), nullptr, nullptr);  // 0.3 s > 0.25 s
  EXPECT_EQ(s3.source, MotionSource::kNone);
  EXPECT_TRUE(s3.camera_prev_cur.isApprox(Pose3::Identity()));
  EXPECT_NEAR(fusion.odom_camera().translation().x(), 0.3, 1e-12);
}

TEST(OdometryFusionTest, PredictsFromTheWheelsElseConstantVelocity) {
  OdometryFusion fusion(RobotFusion());
  Pose3 predicted = Pose3::Identity();
  EXPECT_EQ(fusion.Predict(Sec(1.0), nullptr, &predicted), MotionSource::kNone);  // not started
  WheelOdometryBuffer wheel;
  ASSERT_TRUE(wheel.Add(Sec(1.0), Planar(0.0, 0.0, 0)).ok());
  ASSERT_TRUE(wheel.Add(Sec(1.4), Planar(0.16, 0.0, 4)).ok());
  fusion.Update(Sec(1.0), nullptr, &wheel);
  // Wheels: the base motion seen from the camera, 0.2 m ahead of the base and looking along x.
  ASSERT_EQ(fusion.Predict(Sec(1.4), &wheel, &predicted), MotionSource::kWheel);
  const Pose3& base_to_camera = RobotFusion().base_to_camera;
  const Pose3 expected = base_to_camera.inverse() * Planar(0.16, 0.0, 4) * base_to_camera;
  EXPECT_TRUE(predicted.isApprox(expected, 1e-9));
  // Predict does not move the odometry.
  EXPECT_TRUE(fusion.odom_base().isApprox(Planar(0.0, 0.0, 0), 1e-12));
  // Without wheels: the last velocity, as long as constant velocity may be held.
  const Pose3 step = MakePose(Vec3(0.0, 0.0, 0.1), Quat::Identity());
  fusion.Update(Sec(1.1), &step, nullptr);
  ASSERT_EQ(fusion.Predict(Sec(1.3), nullptr, &predicted), MotionSource::kConstantVelocity);
  EXPECT_NEAR(predicted.translation().z(), 0.2, 1e-9);
  EXPECT_EQ(fusion.Predict(Sec(1.7), nullptr, &predicted), MotionSource::kNone);  // > 0.5 s
}

TEST(OdometryFusionTest, StartsAtTheWheelPose) {
  WheelOdometryBuffer wheel;
  ASSERT_TRUE(wheel.Add(Sec(1.0), Planar(2.0, 1.0, 90)).ok());
  ASSERT_TRUE(wheel.Add(Sec(2.0), Planar(2.0, 1.5, 90)).ok());
  OdometryFusion fusion(RobotFusion());
  fusion.Update(Sec(1.0), nullptr, &wheel);
  EXPECT_TRUE(fusion.odom_base().isApprox(Planar(2.0, 1.0, 90), 1e-9));
  EXPECT_TRUE(
      fusion.odom_camera().isApprox(Planar(2.0, 1.0, 90) * RobotFusion().base_to_camera, 1e-9));
}

}  // namespace
}  // namespace icgm
