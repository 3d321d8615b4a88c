// Wheel odometry reproduces the configured systematic errors and drift statistics.
#include "core/sim/wheel_odometry.h"

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

namespace icgm::sim {
namespace {

// Straight drive along a heading of 0.3 rad at 0.5 m/s, 10 Hz.
std::vector<PlanarPose> StraightTruth(double length_m) {
  std::vector<PlanarPose> truth;
  const double step = 0.05, yaw = 0.3;
  for (double s = 0.0; s <= length_m + 1e-9; s += step) {
    truth.push_back({1.0 + s * std::cos(yaw), 2.0 + s * std::sin(yaw), yaw});
  }
  return truth;
}

// A circle of radius 3 m, counter-clockwise.
std::vector<PlanarPose> CircleTruth() {
  std::vector<PlanarPose> truth;
  for (int i = 0; i <= 400; ++i) {
    const double a = 2 * M_PI * i / 400.0;
    truth.push_back({3.0 * std::sin(a), 3.0 - 3.0 * std::cos(a), a});
  }
  return truth;
}

TEST(WheelOdometryTest, WithoutErrorsEqualsRelativeGroundTruth) {
  OdometryNoiseOptions exact;
  exact.scale_error = 0.0;
  exact.heading_bias_rad_per_m = 0.0;
  exact.distance_noise_m_per_sqrt_m = 0.0;
  exact.heading_noise_rad_per_sqrt_m = 0.0;
  Rng rng(1);
  const auto truth = CircleTruth();
  const auto odom = SimulateWheelOdometry(truth, 0.1, exact, rng);
  ASSERT_EQ(odom.size(), truth.size());
  const Pose3 T0_inv = ToPose3(truth[0]).inverse();
  for (size_t i = 0; i < truth.size(); i += 17) {
    const Pose3 expected = T0_inv * ToPose3(truth[i]);
    EXPECT_LT((odom[i].T_odom_base.translation() - expected.translation()).norm(), 1e-9) << i;
    EXPECT_LT(RotationAngleRad(Between(expected, odom[i].T_odom_base)), 1e-9) << i;
  }
  // Velocities of a 3 m circle: |v| = step / dt, omega = |v| / r.
  const double v = 2 * M_PI * 3.0 / 400.0 / 0.1;
  EXPECT_NEAR(odom[10].linear_velocity_mps.norm(), v, 1e-3);
  EXPECT_NEAR(odom[10].angular_velocity_rps.z(), v / 3.0, 1e-3);
}

TEST(WheelOdometryTest, ScaleErrorAndHeadingBiasOverAStraightSegment) {
  OdometryNoiseOptions o;
  o.scale_error = 0.03;
  o.heading_bias_rad_per_m = 0.004;
  o.distance_noise_m_per_sqrt_m = 0.003;
  o.heading_noise_rad_per_sqrt_m = 0.001;
  const double length = 20.0;
  const auto truth = StraightTruth(length);
  Rng rng(7);
  const auto odom = SimulateWheelOdometry(truth, 0.1, o, rng);
  // Distance driven as the sum of measured increments (path length of the odometry).
  double path = 0.0;
  for (size_t i = 1; i < odom.size(); ++i) {
    path += (odom[i].T_odom_base.translation() - odom[i - 1].T_odom_base.translation()).norm();
  }
  const double sigma_path = o.distance_noise_m_per_sqrt_m * std::sqrt(length);
  EXPECT_NEAR(path / length, 1.0 + o.scale_error, 4.0 * sigma_path / length);
  const double yaw = Eigen::AngleAxisd(odom.back().T_odom_base.linear()).angle();
  const double sigma_yaw = o.heading_noise_rad_per_sqrt_m * std::sqrt(length);
  EXPECT_NEAR(yaw, o.heading_bias_rad_per_m * length, 4.0 * sigma_yaw);
}

TEST(WheelOdometryTest, RandomDriftGrowsWithSqrtDistance) {
  OdometryNoiseOptions o;
  o.scale_error = 0.0;
  o.heading_bias_rad_per_m = 0.0;
  o.distance_noise_m_per_sqrt_m = 0.01;
  o.heading_noise_rad_per_sqrt_m = 0.0;
  const double length = 10.0;
  const auto truth = StraightTruth(length);
  const int runs = 400;
  double sum = 0.0, sum_sq = 0.0;
  for (int r = 0; r < runs; ++r) {
    Rng rng(100 + r);
    const auto odom = SimulateWheelOdometry(truth, 0.1, o, rng);
    const double err = odom.back().T_odom_base.translation().norm() - length;
    sum += err;
    sum_sq += err * err;
  }
  const double mean = sum / runs, stddev = std::sqrt(sum_sq / runs - mean * mean);
  const double expected = o.distance_noise_m_per_sqrt_m * std::sqrt(length);
  EXPECT_NEAR(mean, 0.0, 4.0 * expected / std::sqrt(runs));
  EXPECT_NEAR(stddev, expected, 0.15 * expected);
}

}  // namespace
}  // namespace icgm::sim
