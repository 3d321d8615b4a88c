#include "ros_bridge/odometry_covariance.h"

#include <random>
#include <vector>

#include <gtest/gtest.h>

#include "core/map/se3_geodesic.h"

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

// A camera on a mast, looking forward (optical z along the base's x).
Pose3 MastCamera() {
  return MakePose({0.2, -0.05, 0.6}, Quat(Eigen::AngleAxisd(-M_PI / 2, Vec3::UnitZ()) *
                                          Eigen::AngleAxisd(-M_PI / 2, Vec3::UnitX())));
}

Mat6 StepCovariance() {
  Mat6 c = Mat6::Zero();
  c.diagonal() << 4e-6, 1e-6, 9e-6, 2e-6, 1e-6, 3e-6;
  c(0, 4) = c(4, 0) = 1e-6;
  c(2, 3) = c(3, 2) = -1.5e-6;
  return c;
}

// The base drives an arc at a known body velocity: the step's twist is that velocity, in the
// base frame, whatever the camera mounting.
TEST(StepTwistTest, RecoversTheBaseVelocityOfAKnownArc) {
  Vec6 velocity;
  velocity << 0.8, 0.05, 0.0, 0.0, 0.02, 0.6;  // m/s, rad/s in base_link
  const double dt_s = 0.1;
  const Pose3 base_step = GeodesicExp(velocity * dt_s);
  const Pose3 x = MastCamera();
  const Pose3 camera_step = x.inverse() * base_step * x;
  const StepTwist t = BaseStepTwist(camera_step, StepCovariance(), x, dt_s);
  for (int i = 0; i < 6; ++i) EXPECT_NEAR(t.twist(i), velocity(i), 1e-9) << "component " << i;
  // Standing still: zero twist, and the covariance is the step's over dt^2 moved into the base.
  const StepTwist still =
      BaseStepTwist(Pose3::Identity(), StepCovariance(), Pose3::Identity(), 0.5);
  EXPECT_LT(still.twist.norm(), 1e-12);
  EXPECT_LT((still.covariance - StepCovariance() / 0.25).norm(),
            1e-9 * StepCovariance().norm() / 0.25);
}

// Monte Carlo against the definition: perturb the camera step with its covariance (right
// perturbation in the camera frame, the registration convention), compute the base twist of
// each sample, and compare their spread with the predicted covariance. The step turns 0.3 rad
// and the camera is rotated and offset on the base, so neither the adjoint nor the log Jacobian
// is the identity here.
TEST(StepTwistTest, CovarianceMatchesSampledRegistrationErrors) {
  Vec6 velocity;
  velocity << 0.5, 0.0, 0.0, 0.0, 0.0, 1.5;
  const double dt_s = 0.2;
  const Pose3 x = MastCamera();
  const Pose3 camera_step = x.inverse() * GeodesicExp(velocity * dt_s) * x;
  const Mat6 step_covariance = StepCovariance();
  const StepTwist predicted = BaseStepTwist(camera_step, step_covariance, x, dt_s);

  std::mt19937 rng(11);
  std::normal_distribution<double> normal;
  const Eigen::LLT<Mat6> llt(step_covariance);
  const int n = 40000;
  std::vector<Vec6> samples;
  Vec6 mean = Vec6::Zero();
  for (int s = 0; s < n; ++s) {
    Vec6 z;
    for (int i = 0; i < 6; ++i) z(i) = normal(rng);
    const Pose3 noisy = camera_step * ExpSE3(llt.matrixL() * z);
    samples.push_back(GeodesicLog(x * noisy * x.inverse()) / dt_s);
    mean += samples.back() / n;
  }
  Mat6 sampled = Mat6::Zero();
  for (const Vec6& v : samples) sampled += (v - mean) * (v - mean).transpose() / (n - 1);
  for (int i = 0; i < 6; ++i) {
    EXPECT_NEAR(mean(i), predicted.twist(i), 0.03 * std::sqrt(sampled(i, i)) + 1e-9) << i;
    for (int j = 0; j < 6; ++j) {
      const double scale = std::sqrt(sampled(i, i) * sampled(j, j));
      EXPECT_NEAR(predicted.covariance(i, j), sampled(i, j), 0.05 * scale)
          << "entry " << i << "," << j;
    }
  }
  // The plain step covariance over dt^2 (camera frame, no log Jacobian) is far off here: the
  // comparison above can tell them apart.
  EXPECT_GT((step_covariance / (dt_s * dt_s) - sampled).norm(), 0.5 * sampled.norm());
}

TEST(StepTwistTest, ScalesWithOneOverDtSquaredAndFillsTheMessage) {
  const Pose3 x = MastCamera();
  Vec6 velocity;
  velocity << 0.3, 0.0, 0.0, 0.0, 0.0, 0.4;
  const Pose3 camera_step = x.inverse() * GeodesicExp(velocity * 0.1) * x;
  const StepTwist a = BaseStepTwist(camera_step, StepCovariance(), x, 0.1);
  const StepTwist b = BaseStepTwist(camera_step, StepCovariance(), x, 0.05);
  EXPECT_LT((b.covariance - 4.0 * a.covariance).norm(), 1e-9 * b.covariance.norm());
  EXPECT_LT((b.twist - 2.0 * a.twist).norm(), 1e-12);

  const geometry_msgs::TwistWithCovariance msg = ToTwistWithCovarianceMsg(a);
  EXPECT_DOUBLE_EQ(msg.twist.linear.x, a.twist(0));
  EXPECT_DOUBLE_EQ(msg.twist.linear.y, a.twist(1));
  EXPECT_DOUBLE_EQ(msg.twist.linear.z, a.twist(2));
  EXPECT_DOUBLE_EQ(msg.twist.angular.x, a.twist(3));
  EXPECT_DOUBLE_EQ(msg.twist.angular.y, a.twist(4));
  EXPECT_DOUBLE_EQ(msg.twist.angular.z, a.twist(5));
  for (int i = 0; i < 6; ++i)
    for (int j = 0; j < 6; ++j) EXPECT_DOUBLE_EQ(msg.covariance[6 * i + j], a.covariance(i, j));
  // Symmetric and positive definite, as a covariance must be.
  EXPECT_LT((a.covariance - a.covariance.transpose()).norm(), 1e-15 * a.covariance.norm());
  EXPECT_EQ(Eigen::LLT<Mat6>(a.covariance).info(), Eigen::Success);
}

// The fused odometry message carries the base pose, its covariance and the step's twist as given.
TEST(FusedOdometryMsgTest, CarriesPoseCovarianceAndTwist) {
  const Pose3 x = MastCamera();
  Vec6 velocity;
  velocity << 0.3, 0.0, 0.0, 0.0, 0.0, 0.4;
  const StepTwist twist =
      BaseStepTwist(x.inverse() * GeodesicExp(velocity * 0.1) * x, StepCovariance(), x, 0.1);
  Pose3 odom_base = Pose3::Identity();
  odom_base.translation() = Eigen::Vector3d(1.0, -2.0, 0.5);
  std::array<double, 36> covariance{};
  for (size_t i = 0; i < covariance.size(); ++i) covariance[i] = 0.001 * static_cast<double>(i);
  const nav_msgs::Odometry msg =
      ToFusedOdometryMsg(ros::Time(12, 5), "odom", "base_link", odom_base, covariance, twist);
  EXPECT_EQ(msg.header.stamp, ros::Time(12, 5));
  EXPECT_EQ(msg.header.frame_id, "odom");
  EXPECT_EQ(msg.child_frame_id, "base_link");
  EXPECT_DOUBLE_EQ(msg.pose.pose.position.x, 1.0);
  EXPECT_DOUBLE_EQ(msg.pose.pose.position.y, -2.0);
  EXPECT_DOUBLE_EQ(msg.pose.pose.position.z, 0.5);
  EXPECT_DOUBLE_EQ(msg.pose.pose.orientation.w, 1.0);
  for (size_t i = 0; i < covariance.size(); ++i) EXPECT_EQ(msg.pose.covariance[i], covariance[i]);
  EXPECT_DOUBLE_EQ(msg.twist.twist.linear.x, twist.twist(0));
  EXPECT_DOUBLE_EQ(msg.twist.twist.angular.z, twist.twist(5));
  EXPECT_DOUBLE_EQ(msg.twist.covariance[0], twist.covariance(0, 0));
}

}  // namespace
}  // namespace icgm::ros_bridge
