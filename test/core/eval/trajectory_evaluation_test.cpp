#include "core/eval/trajectory_evaluation.h"

#include <cmath>
#include <random>

#include <gtest/gtest.h>

namespace icgm {
namespace {

constexpr double kRate = 30.0;  // Hz, like a Kinect

// A helix with a turning heading: positions span 3-D, rotations vary about all axes.
Trajectory Helix(int n, bool rotate_about_z_only = false) {
  Trajectory t;
  for (int i = 0; i < n; ++i) {
    const double s = i / kRate;
    StampedPose sp;
    sp.stamp = Time::FromSeconds(1000.0 + s);
    const Vec3 p(std::cos(0.5 * s) * 2.0, std::sin(0.5 * s) * 1.5, 0.1 * s);
    Quat q(Eigen::AngleAxisd(0.5 * s, Vec3::UnitZ()));
    if (!rotate_about_z_only) q = q * Quat(Eigen::AngleAxisd(0.2 * std::sin(s), Vec3::UnitX()));
    sp.pose = MakePose(p, q);
    t.push_back(sp);
  }
  return t;
}

Pose3 RandomPose(std::mt19937* rng) {
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  return MakePose(Vec3(u(*rng), u(*rng), u(*rng)) * 10.0,
                  Quat(Eigen::Vector4d(u(*rng), u(*rng), u(*rng), u(*rng)).normalized()));
}

TEST(TrajectoryEvaluationTest, RigidlyMovedCopyHasZeroError) {
  std::mt19937 rng(1);
  const Trajectory gt = Helix(300);
  const Pose3 offset = RandomPose(&rng);
  Trajectory est = gt;
  for (auto& sp : est) sp.pose = offset * sp.pose;
  TrajectoryEvaluation ev;
  ASSERT_TRUE(EvaluateTrajectory(gt, est, {}, &ev).ok());
  EXPECT_EQ(ev.num_associated(), 300u);
  EXPECT_LT(ev.ate.rmse, 1e-9);
  EXPECT_LT(ev.ate.max, 1e-9);
  EXPECT_LT(ev.rpe_translation_m_per_s.max, 1e-9);
  EXPECT_LT(ev.rpe_rotation_deg_per_s.max, 1e-8);
  EXPECT_TRUE(ev.alignment.AsPose().isApprox(offset.inverse(), 1e-9));
  // Full poses (not only positions) line up after alignment.
  for (size_t k = 0; k < ev.num_associated(); ++k) {
    EXPECT_TRUE(ev.aligned_estimate[k].isApprox(ev.groundtruth[k], 1e-9));
  }
}

TEST(TrajectoryEvaluationTest, AlternatingOffsetGivesKnownAte) {
  // The ground truth pauses for two frames at each position, and the estimate is offset by
  // +d / -d along y on those two frames. The offsets cancel in the centroid and in the
  // cross-covariance, so the best alignment is the identity and every error is exactly d.
  const double d = 0.03;
  Trajectory gt = Helix(400);
  for (size_t i = 1; i < gt.size(); i += 2) gt[i].pose = gt[i - 1].pose;
  Trajectory est = gt;
  for (size_t i = 0; i < est.size(); ++i) {
    est[i].pose.translation().y() += (i % 2 == 0 ? d : -d);
  }
  TrajectoryEvaluation ev;
  ASSERT_TRUE(EvaluateTrajectory(gt, est, {}, &ev).ok());
  EXPECT_NEAR(ev.ate.rmse, d, 1e-9);
  EXPECT_NEAR(ev.ate.mean, d, 1e-9);
  EXPECT_NEAR(ev.ate.median, d, 1e-9);
  EXPECT_NEAR(ev.ate.max, d, 1e-9);
  EXPECT_LT((ev.alignment.rotation - Eigen::Matrix3d::Identity()).norm(), 1e-9);
}

TEST(TrajectoryEvaluationTest, Sim3RecoversScale) {
  std::mt19937 rng(2);
  const Trajectory gt = Helix(200);
  const double scale = 0.37;  // a monocular estimate in arbitrary units
  const Pose3 offset = RandomPose(&rng);
  Trajectory est = gt;
  for (auto& sp : est) {
    sp.pose = offset * sp.pose;
    sp.pose.translation() /= scale;
  }
  TrajectoryEvalOptions opt;
  opt.estimate_scale = true;
  TrajectoryEvaluation ev;
  ASSERT_TRUE(EvaluateTrajectory(gt, est, opt, &ev).ok());
  EXPECT_NEAR(ev.alignment.scale, scale, 1e-9);
  EXPECT_LT(ev.ate.rmse, 1e-9);
  EXPECT_LT(ev.rpe_translation_m_per_s.max, 1e-9);  // RPE uses the scaled estimate
  // Rigid alignment cannot explain the scale.
  TrajectoryEvaluation rigid;
  ASSERT_TRUE(EvaluateTrajectory(gt, est, {}, &rigid).ok());
  EXPECT_EQ(rigid.alignment.scale, 1.0);
  EXPECT_GT(rigid.ate.rmse, 0.1);
}

TEST(TrajectoryEvaluationTest, RpeOfConstantTranslationDrift) {
  // The estimate drifts at a constant world velocity v: every relative motion is off by
  // v * dt, so RPE translation is |v| m/s for all pairs and RPE rotation is zero.
  const Vec3 v(0.02, -0.01, 0.005);
  const Trajectory gt = Helix(300);  // 10 s
  Trajectory est = gt;
  for (auto& sp : est) sp.pose.translation() += v * DurationSeconds(sp.stamp, gt[0].stamp);
  TrajectoryEvaluation ev;
  ASSERT_TRUE(EvaluateTrajectory(gt, est, {}, &ev).ok());
  EXPECT_EQ(ev.rpe_translation_m_per_s.count, 300u - 30u);  // pairs exactly 1 s apart
  EXPECT_NEAR(ev.rpe_translation_m_per_s.min, v.norm(), 1e-9);
  EXPECT_NEAR(ev.rpe_translation_m_per_s.max, v.norm(), 1e-9);
  EXPECT_LT(ev.rpe_rotation_deg_per_s.max, 1e-8);
  EXPECT_GT(ev.ate.rmse, 0.01);  // drift is not a rigid motion
}

TEST(TrajectoryEvaluationTest, RpeOfConstantRotationDrift) {
  // Heading drifts at w rad/s about the same axis the ground truth turns about, so the
  // relative rotation error over dt is exactly w * dt.
  const double w = 0.01;
  const Trajectory gt = Helix(300, /*rotate_about_z_only=*/true);
  Trajectory est = gt;
  for (auto& sp : est) {
    const double s = DurationSeconds(sp.stamp, gt[0].stamp);
    sp.pose.linear() = sp.pose.linear() * Eigen::AngleAxisd(w * s, Vec3::UnitZ()).matrix();
  }
  TrajectoryEvalOptions opt;
  opt.rpe_delta_s = 2.0;
  TrajectoryEvaluation ev;
  ASSERT_TRUE(EvaluateTrajectory(gt, est, opt, &ev).ok());
  EXPECT_EQ(ev.rpe_rotation_deg_per_s.count, 300u - 60u);
  const double expected_deg_per_s = w * 180.0 / M_PI;
  EXPECT_NEAR(ev.rpe_rotation_deg_per_s.min, expected_deg_per_s, 1e-7);
  EXPECT_NEAR(ev.rpe_rotation_deg_per_s.max, expected_deg_per_s, 1e-7);
  EXPECT_LT(ev.ate.max, 1e-9);  // positions are untouched
}

TEST(TrajectoryEvaluationTest, AssociatesByStampWithinWindow) {
  const Trajectory gt = Helix(300);
  Trajectory est;
  // Every third pose, stamped 7 ms late, unsorted.
  for (size_t i = 0; i < gt.size(); i += 3) {
    StampedPose sp = gt[i];
    sp.stamp = Time::FromNanoseconds(sp.stamp.nanoseconds() + 7000000);
    est.insert(est.begin(), sp);
  }
  TrajectoryEvaluation ev;
  ASSERT_TRUE(EvaluateTrajectory(gt, est, {}, &ev).ok());
  EXPECT_EQ(ev.num_associated(), 100u);
  EXPECT_EQ(ev.num_estimate, 100u);
  EXPECT_EQ(ev.num_groundtruth, 300u);
  EXPECT_LT(ev.ate.max, 1e-9);
  EXPECT_LT(ev.stamps.front(), ev.stamps.back());

  TrajectoryEvalOptions tight;
  tight.max_dt_s = 0.005;
  const Status s = EvaluateTrajectory(gt, est, tight, &ev);
  EXPECT_FALSE(s.ok());
  EXPECT_NE(s.reason().find("only 0"), std::string::npos) << s.reason();
}

TEST(TrajectoryEvaluationTest, FailuresHaveReasons) {
  const Trajectory gt = Helix(100);
  TrajectoryEvaluation ev;
  EXPECT_FALSE(EvaluateTrajectory(gt, {}, {}, &ev).ok());
  EXPECT_FALSE(EvaluateTrajectory({}, gt, {}, &ev).ok());
  Trajectory line = gt;
  for (size_t i = 0; i < line.size(); ++i) line[i].pose.translation() = Vec3(0.01 * i, 0, 0);
  const Status s = EvaluateTrajectory(gt, line, {}, &ev);
  EXPECT_FALSE(s.ok());
  EXPECT_NE(s.reason().find("collinear"), std::string::npos) << s.reason();
  TrajectoryEvalOptions bad;
  bad.rpe_delta_s = 0.0;
  EXPECT_FALSE(EvaluateTrajectory(gt, gt, bad, &ev).ok());
  bad = {};
  bad.max_dt_s = -1.0;
  EXPECT_FALSE(EvaluateTrajectory(gt, gt, bad, &ev).ok());
}

TEST(TrajectoryEvaluationTest, ShortTrajectoryHasNoRpe) {
  const Trajectory gt = Helix(20);  // 0.63 s
  TrajectoryEvaluation ev;
  ASSERT_TRUE(EvaluateTrajectory(gt, gt, {}, &ev).ok());
  EXPECT_EQ(ev.rpe_translation_m_per_s.count, 0u);
  EXPECT_EQ(ev.ate.count, 20u);
}

}  // namespace
}  // namespace icgm
