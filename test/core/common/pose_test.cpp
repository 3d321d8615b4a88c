#include "core/common/pose.h"

#include <gtest/gtest.h>

namespace icgm {
namespace {

TEST(PoseTest, BetweenInvertsCompose) {
  const Pose3 a = MakePose({1, 2, 3}, Quat(Eigen::AngleAxisd(0.3, Vec3(0, 0, 1))));
  const Pose3 r = MakePose({0.1, -0.2, 0.05}, Quat(Eigen::AngleAxisd(0.1, Vec3(1, 0, 0))));
  const Pose3 b = Compose(a, r);
  EXPECT_TRUE(Between(a, b).isApprox(r, 1e-12));
}

TEST(PoseTest, RotationAngle) {
  const Pose3 p = MakePose({0, 0, 0}, Quat(Eigen::AngleAxisd(0.7, Vec3(0, 1, 0))));
  EXPECT_NEAR(RotationAngleRad(p), 0.7, 1e-12);
}

TEST(PoseTest, InterpolateHalfway) {
  const Pose3 a = Pose3::Identity();
  const Pose3 b = MakePose({2, 0, 0}, Quat(Eigen::AngleAxisd(1.0, Vec3(0, 0, 1))));
  const Pose3 m = Interpolate(a, b, 0.5);
  EXPECT_NEAR(m.translation().x(), 1.0, 1e-12);
  EXPECT_NEAR(RotationAngleRad(m), 0.5, 1e-12);
}

TEST(PoseTest, ExpInvertsLog) {
  const Pose3 p = MakePose({0.4, -1, 2}, Quat(Eigen::AngleAxisd(2.5, Vec3(1, 2, 3).normalized())));
  EXPECT_TRUE(ExpSE3(LogSE3(p)).isApprox(p, 1e-12));
}

}  // namespace
}  // namespace icgm
