#include "core/odometry/vision_step.h"

#include <gtest/gtest.h>

#include "core/odometry/odometry_fusion.h"

namespace icgm {
namespace {

TEST(VisionStepTest, VisionGivesTheFrontEndsStep) {
  FrontendFrameResult frame;
  frame.source = MotionSource::kVision;
  frame.odom_camera = MakePose({1.0, 0.2, 0.0}, Quat(Eigen::AngleAxisd(0.1, Vec3::UnitY())));
  frame.registration.inliers = 55;
  const Pose3 previous = MakePose({0.9, 0.2, 0.0}, Quat::Identity());
  const RegistrationResult r = VisionStep(frame, previous);
  EXPECT_TRUE(r.status.ok());
  EXPECT_TRUE((previous * r.relative_pose).isApprox(frame.odom_camera, 1e-12));
  EXPECT_EQ(r.inliers, 55u);
}

TEST(VisionStepTest, OtherSourcesAreFailuresWithAReason) {
  FrontendFrameResult frame;
  frame.source = MotionSource::kWheel;  // registration succeeded but the gate chose the wheels
  EXPECT_EQ(VisionStep(frame, Pose3::Identity()).status.reason(),
            "no vision motion for this frame");
  frame.registration.status = Status::Error("too few inliers");
  EXPECT_EQ(VisionStep(frame, Pose3::Identity()).status.reason(), "too few inliers");
}

// Consecutive frames: none for the first, then each frame's step from the one before, chained
// back to the poses the front end gave.
TEST(VisionStepTest, ChainStepsFromThePreviousFrame) {
  VisionStepChain chain;
  FrontendFrameResult frame;
  frame.source = MotionSource::kVision;
  frame.stamp = Time::FromSeconds(1.0);
  frame.odom_camera = MakePose({0.1, 0.0, 0.0}, Quat::Identity());
  EXPECT_FALSE(chain.Add(frame).has_value());
  Pose3 chained = frame.odom_camera;
  for (int i = 2; i <= 4; ++i) {
    frame.stamp = Time::FromSeconds(i);
    frame.odom_camera = MakePose({0.1 * i, 0.02 * i, 0.0},
                                 Quat(Eigen::AngleAxisd(0.05 * i, Vec3::UnitY())));
    frame.source = i == 3 ? MotionSource::kWheel : MotionSource::kVision;
    const std::optional<VisionStepChain::Step> step = chain.Add(frame);
    ASSERT_TRUE(step.has_value());
    EXPECT_EQ(step->stamp, Time::FromSeconds(i));
    EXPECT_EQ(step->reference_stamp, Time::FromSeconds(i - 1));
    if (i == 3) {
      EXPECT_FALSE(step->result.status.ok());  // not measured by vision
      chained = frame.odom_camera;
      continue;
    }
    ASSERT_TRUE(step->result.status.ok());
    chained = chained * step->result.relative_pose;
    EXPECT_TRUE(chained.isApprox(frame.odom_camera, 1e-12)) << "frame " << i;
  }
}

}  // namespace
}  // namespace icgm
