#include "ros_bridge/odometry_covariance.h"

#include <random>
#include <vector>

#include <gtest/gtest.h>

namespace icgm::ros_bridge {
namespace {

using Vec6 = Eigen::Matrix<double, 6, 1>;

// Monte Carlo: perturb every step of a chain with its covariance (right perturbation in the
// camera frame, the registration convention) and compare the spread of the resulting base pose
// (position error, rotation error on the left, in the odometry frame) with BaseMsg.
TEST(OdometryCovarianceTest, MatchesSampledChainInMessageConvention) {
  const Pose3 base_to_camera =
      MakePose({0.2, -0.05, 0.6}, Quat(Eigen::AngleAxisd(-M_PI / 2, Vec3::UnitX())));
  std::vector<Pose3> steps;
  std::vector<Mat6> covariances;
  for (int k = 0; k < 4; ++k) {
    steps.push_back(MakePose({0.05, 0.01 * k, 0.3},
                             Quat(Eigen::AngleAxisd(0.2, Vec3(0.1, 1.0, 0.2).normalized()))));
    Mat6 c = Mat6::Zero();
    c.diagonal() << 1e-6, 4e-6, 9e-6, 1e-6, 2e-6, 3e-6;
    c(0, 4) = c(4, 0) = 5e-7;
    covariances.push_back(c * (k + 1));
  }
  OdometryCovariance covariance;
  Pose3 odom_camera = MakePose({1, 2, 0.5}, Quat::Identity()) * base_to_camera;
  const Pose3 start = odom_camera;
  for (size_t k = 0; k < steps.size(); ++k) {
    const Pose3 next = odom_camera * steps[k];
    covariance.AddStep(odom_camera, next, covariances[k]);
    odom_camera = next;
  }
  const std::array<double, 36> msg = covariance.BaseMsg(odom_camera, base_to_camera);
  const Pose3 odom_base = odom_camera * base_to_camera.inverse();

  std::mt19937 rng(3);
  std::normal_distribution<double> normal;
  const int n = 40000;
  Mat6 sampled = Mat6::Zero();
  for (int s = 0; s < n; ++s) {
    Pose3 pose = start;
    for (size_t k = 0; k < steps.size(); ++k) {
      const Eigen::LLT<Mat6> llt(covariances[k]);
      Vec6 z;
      for (int i = 0; i < 6; ++i) z(i) = normal(rng);
      pose = pose * steps[k] * ExpSE3(llt.matrixL() * z);
    }
    const Pose3 base = pose * base_to_camera.inverse();
    Vec6 e;
    e.head<3>() = base.translation() - odom_base.translation();
    const Eigen::AngleAxisd r(base.linear() * odom_base.linear().transpose());
    e.tail<3>() = r.angle() * r.axis();
    sampled += e * e.transpose() / n;
  }
  for (int i = 0; i < 6; ++i) {
    for (int j = 0; j < 6; ++j) {
      const double scale = std::sqrt(sampled(i, i) * sampled(j, j));
      EXPECT_NEAR(msg[6 * i + j], sampled(i, j), 0.05 * scale) << "entry " << i << "," << j;
    }
  }
  // Position error of the base includes the lever arm: larger than the camera's own.
  EXPECT_GT(msg[0] + msg[7] + msg[14], 0.0);
}

TEST(OdometryCovarianceTest, IsotropicStepAndZeroStart) {
  const Mat6 c = IsotropicStepCovariance(0.01, 0.002);
  EXPECT_DOUBLE_EQ(c(0, 0), 1e-4);
  EXPECT_DOUBLE_EQ(c(5, 5), 4e-6);
  EXPECT_DOUBLE_EQ(c(0, 5), 0.0);
  OdometryCovariance none;
  for (double v : none.BaseMsg(Pose3::Identity(), Pose3::Identity())) EXPECT_EQ(v, 0.0);
}

}  // namespace
}  // namespace icgm::ros_bridge
