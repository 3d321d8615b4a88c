#include "ros_bridge/registration_msgs.h"

#include <gtest/gtest.h>

#include "ros_bridge/conversions.h"

namespace icgm::ros_bridge {
namespace {

TEST(RegistrationMsgsTest, RoundTripSuccessAndFailure) {
  RegistrationResult r;
  r.relative_pose = MakePose({0.1, 0.02, -0.03}, Quat(Eigen::AngleAxisd(0.05, Vec3::UnitY())));
  r.covariance = Mat6::Identity() * 1e-4;
  r.covariance(0, 5) = r.covariance(5, 0) = 2e-6;
  r.matches_2d = 120;
  r.matches_3d = 100;
  r.inliers = 80;
  r.inlier_ratio = 0.8;
  r.rmse_m = 0.012;
  const auto msg = ToRegistrationMsg(r, Time::FromSeconds(2), Time::FromSeconds(1.9), "cam");
  EXPECT_TRUE(msg.success);
  EXPECT_EQ(FromRos(msg.reference_stamp), Time::FromSeconds(1.9));
  const RegistrationResult back = FromRegistrationMsg(msg);
  EXPECT_TRUE(back.status.ok());
  EXPECT_TRUE(back.relative_pose.isApprox(r.relative_pose, 1e-12));
  EXPECT_TRUE(back.covariance.isApprox(r.covariance, 1e-15));
  EXPECT_EQ(back.inliers, 80u);
  EXPECT_EQ(back.matches_3d, 100u);

  r.status = Status::Error("too few inliers: 8 < 10");
  const RegistrationResult failed =
      FromRegistrationMsg(ToRegistrationMsg(r, Time(), Time(), "cam"));
  EXPECT_FALSE(failed.status.ok());
  EXPECT_EQ(failed.status.reason(), "too few inliers: 8 < 10");
}

}  // namespace
}  // namespace icgm::ros_bridge
