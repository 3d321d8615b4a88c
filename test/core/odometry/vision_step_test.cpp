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

}  // namespace
}  // namespace icgm
