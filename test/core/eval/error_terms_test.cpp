#include "core/eval/error_terms.h"

#include <cmath>

#include <gtest/gtest.h>

namespace icgm {
namespace {

// A hand-held camera moving back and forth along all three axes of its own (fixed) frame.
Vec3 CameraFramePosition(double t) {
  return {0.3 * std::sin(1.1 * t), 0.2 * std::sin(1.7 * t + 0.5), 0.15 * std::sin(0.7 * t + 1.0)};
}

const Quat kOrientation(Eigen::AngleAxisd(0.4, Vec3(1.0, 2.0, 0.5).normalized()));
const Vec3 kStart(1.0, -2.0, 0.5);

Pose3 Truth(double t) { return MakePose(kStart + kOrientation * CameraFramePosition(t), kOrientation); }

// Ground truth at 300 Hz (every estimate stamp has its own); an estimate at 30 Hz whose axis k runs lead_s(k) ahead of the truth
// and moves (1 + scale_error(k)) times as far.
void MakeTrajectories(const Vec3& lead_s, const Vec3& scale_error, Trajectory* gt,
                      Trajectory* est) {
  for (int i = 0; i <= 9000; ++i) {
    const double t = i / 300.0;
    gt->push_back({Time::FromSeconds(100.0 + t), Truth(t)});
  }
  const Vec3 p0 = CameraFramePosition(0.0);
  for (int i = 10; i < 890; ++i) {
    const double t = i / 30.0;
    Vec3 p;
    for (int k = 0; k < 3; ++k) {
      p(k) = p0(k) + (1.0 + scale_error(k)) * (CameraFramePosition(t + lead_s(k))(k) - p0(k));
    }
    est->push_back({Time::FromSeconds(100.0 + t), MakePose(kStart + kOrientation * p, kOrientation)});
  }
}

TEST(ErrorTermsTest, RecoversTimeLeadAndScaleErrorPerCameraAxis) {
  const Vec3 lead(0.025, 0.025, -0.013);
  const Vec3 scale(-0.035, -0.03, 0.0);
  Trajectory gt, est;
  MakeTrajectories(lead, scale, &gt, &est);
  TrajectoryEvaluation ev;
  ASSERT_TRUE(EvaluateTrajectory(gt, est, TrajectoryEvalOptions(), &ev).ok());
  ASSERT_GT(ev.ate.rmse, 0.004);
  ErrorTerms terms;
  const Status s = FitErrorTerms(gt, ev, &terms);
  ASSERT_TRUE(s.ok()) << s.reason();
  EXPECT_GT(terms.poses, 800u);
  for (int k = 0; k < 3; ++k) {
    EXPECT_NEAR(terms.lead_s(k), lead(k), 0.003) << "axis " << k;
    EXPECT_NEAR(terms.scale_error(k), scale(k), 0.004) << "axis " << k;
  }
  EXPECT_NEAR(terms.ate_rmse_m, ev.ate.rmse, 1e-9);
  // Both terms explain nearly everything; either alone leaves the other's share.
  EXPECT_LT(terms.rmse_after_both_m, 0.15 * terms.ate_rmse_m);
  EXPECT_GT(terms.rmse_after_lead_m, 3.0 * terms.rmse_after_both_m);
  EXPECT_GT(terms.rmse_after_scale_m, 3.0 * terms.rmse_after_both_m);
}

TEST(ErrorTermsTest, ExactEstimateHasNoTerms) {
  Trajectory gt, est;
  MakeTrajectories(Vec3::Zero(), Vec3::Zero(), &gt, &est);
  TrajectoryEvaluation ev;
  ASSERT_TRUE(EvaluateTrajectory(gt, est, TrajectoryEvalOptions(), &ev).ok());
  ErrorTerms terms;
  ASSERT_TRUE(FitErrorTerms(gt, ev, &terms).ok());
  EXPECT_LT(terms.lead_s.cwiseAbs().maxCoeff(), 1e-4);
  EXPECT_LT(terms.scale_error.cwiseAbs().maxCoeff(), 1e-4);
  EXPECT_LT(terms.ate_rmse_m, 1e-6);
}

TEST(ErrorTermsTest, RefusesMotionThatLeavesAnAxisUnobservable) {
  Trajectory gt, est;
  for (int i = 0; i <= 300; ++i) {
    const double t = i / 30.0;
    const Pose3 p = MakePose(Vec3(0.3 * std::sin(t), 0.0, 0.0), Quat::Identity());
    gt.push_back({Time::FromSeconds(10.0 + t), p});
    est.push_back({Time::FromSeconds(10.0 + t), p});
  }
  TrajectoryEvaluation ev;
  ErrorTerms terms;
  // Collinear positions cannot even be aligned; a short straight track has no y or z motion.
  if (EvaluateTrajectory(gt, est, TrajectoryEvalOptions(), &ev).ok()) {
    EXPECT_FALSE(FitErrorTerms(gt, ev, &terms).ok());
  }
  EXPECT_FALSE(FitErrorTerms(gt, TrajectoryEvaluation(), &terms).ok());
}

}  // namespace
}  // namespace icgm
