#include "core/odometry/velocity_history.h"

#include <cmath>
#include <random>
#include <string>
#include <vector>

#include <gtest/gtest.h>

namespace icgm {
namespace {

Time Frame(int i) { return Time::FromNanoseconds(1'000'000'000LL + i * 33'333'333LL); }

// A hand-held camera moving 3 mm and 0.1 deg per frame (30 Hz), about a tilted axis.
Pose3 TruePose(int i) {
  const Vec3 axis = Vec3(0.2, 1.0, 0.1).normalized();
  return MakePose(Vec3(0.003, -0.001, 0.0005) * i,
                  Quat(Eigen::AngleAxisd(0.1 * M_PI / 180.0 * i, axis)));
}

TEST(VelocityHistoryTest, NeedsTwoPosesAndRespectsTheGap) {
  VelocityHistory h(10, 0.5);
  EXPECT_FALSE(h.PredictStep(Frame(1)).has_value());
  h.Add(Frame(0), TruePose(0));
  EXPECT_FALSE(h.PredictStep(Frame(1)).has_value());
  h.Add(Frame(1), TruePose(1));
  EXPECT_TRUE(h.PredictStep(Frame(2)).has_value());
  // A frame 0.6 s after the newest pose: no prediction.
  EXPECT_FALSE(h.PredictStep(Frame(19)).has_value());
  // A gap inside the history restarts it.
  h.Add(Frame(30), TruePose(30));
  EXPECT_EQ(h.size(), 1u);
}

TEST(VelocityHistoryTest, PredictsAConstantVelocityExactly) {
  VelocityHistory h(5, 0.5);
  for (int i = 0; i <= 8; ++i) h.Add(Frame(i), TruePose(i));
  EXPECT_EQ(h.size(), 6u);  // five steps
  const std::optional<Pose3> step = h.PredictStep(Frame(9));
  ASSERT_TRUE(step.has_value());
  const Pose3 truth = Between(TruePose(8), TruePose(9));
  // Within 0.1 mm: the decoupled twist (pose.h LogSE3) leaves out the rotation's second-order
  // effect on the translation over the span.
  EXPECT_LT(TranslationNorm(Between(truth, *step)), 1e-4);
  EXPECT_LT(RotationAngleRad(Between(truth, *step)), 1e-6);
  // Two frame intervals ahead (a dropped frame): twice the step.
  const std::optional<Pose3> two = h.PredictStep(Frame(10));
  ASSERT_TRUE(two.has_value());
  EXPECT_LT(TranslationNorm(Between(Between(TruePose(8), TruePose(10)), *two)), 2e-4);
}

// The velocity itself (the depth timing's and rolling shutter's, depth_timing_averaged_velocity):
// per second, the prediction's step divided by its interval; none from a single pose.
TEST(VelocityHistoryTest, TwistIsTheVelocityPerSecondOfThePrediction) {
  VelocityHistory h(5, 0.5);
  h.Add(Frame(0), TruePose(0));
  EXPECT_FALSE(h.Twist().has_value());
  for (int i = 1; i <= 8; ++i) h.Add(Frame(i), TruePose(i));
  const std::optional<Vec6> twist = h.Twist();
  ASSERT_TRUE(twist.has_value());
  const double dt_s = DurationSeconds(Frame(9), Frame(8));
  const Vec6 step = LogSE3(*h.PredictStep(Frame(9))) / dt_s;
  EXPECT_LT((*twist - step).norm(), 1e-9);
  // 3.2 mm and 0.1 deg per 1/30 s: about 0.095 m/s and 3 deg/s.
  EXPECT_NEAR(twist->head<3>().norm(), TranslationNorm(Between(TruePose(0), TruePose(1))) / dt_s,
              1e-4);
  EXPECT_NEAR(twist->tail<3>().norm(), 0.1 * M_PI / 180.0 / dt_s, 1e-6);
}

// Poses with independent 1.5 cm / 0.5 deg errors per frame (registration noise where walkers
// fill the view) while the camera moves 3 mm per frame: the last step alone predicts mostly the
// noise, ten steps average it down.
TEST(VelocityHistoryTest, TenStepsPredictANoisyPathFarBetterThanTheLastStep) {
  std::mt19937 rng(3);
  std::normal_distribution<double> noise(0.0, 1.0);
  const auto noisy = [&](int i) {
    const Vec3 dt(noise(rng), noise(rng), noise(rng));
    const Vec3 dr(noise(rng), noise(rng), noise(rng));
    return TruePose(i) * MakePose(0.015 * dt, Quat(Eigen::AngleAxisd(
                                                      0.5 * M_PI / 180.0 * dr.norm(),
                                                      dr.normalized())));
  };
  VelocityHistory last(1, 0.5), ten(10, 0.5);
  double err_last = 0.0, err_ten = 0.0;
  int n = 0;
  for (int i = 0; i < 300; ++i) {
    if (i >= 11) {
      const Pose3 truth = Between(TruePose(i - 1), TruePose(i));
      err_last += std::pow(TranslationNorm(Between(truth, *last.PredictStep(Frame(i)))), 2);
      err_ten += std::pow(TranslationNorm(Between(truth, *ten.PredictStep(Frame(i)))), 2);
      ++n;
    }
    const Pose3 p = noisy(i);
    last.Add(Frame(i), p);
    ten.Add(Frame(i), p);
  }
  err_last = std::sqrt(err_last / n);
  err_ten = std::sqrt(err_ten / n);
  // Expected about sqrt(2) * 1.5 cm * sqrt(3) for the last step and a tenth of it for ten.
  EXPECT_GT(err_last, 0.02);
  EXPECT_LT(err_ten, 0.3 * err_last);
}

// One jerk of the hand (a 1 cm step where the camera otherwise moves 3 mm per frame) at the
// start of the history: the mean motion over the steps keeps a share of it for as long as the
// history spans, the median of the single steps ignores it once three steps are known.
TEST(VelocityHistoryTest, MedianIgnoresASingleJerk) {
  const Pose3 jerk = MakePose(Vec3(0.01, 0.0, 0.0), Quat::Identity());
  const auto pose = [&](int i) { return i == 0 ? TruePose(0) : jerk * TruePose(i); };
  VelocityHistory mean(20, 0.5), median(20, 0.5, true);
  for (int i = 0; i <= 6; ++i) {
    mean.Add(Frame(i), pose(i));
    median.Add(Frame(i), pose(i));
  }
  const Pose3 truth = Between(TruePose(6), TruePose(7));
  const double mean_error = TranslationNorm(Between(truth, *mean.PredictStep(Frame(7))));
  const double median_error = TranslationNorm(Between(truth, *median.PredictStep(Frame(7))));
  // The mean carries a sixth of the 1 cm jerk (1.7 mm); the median is within 0.1 mm.
  EXPECT_GT(mean_error, 0.0015);
  EXPECT_LT(median_error, 1e-4);
  // Exact on a constant velocity too (as the mean).
  VelocityHistory constant(5, 0.5, true);
  for (int i = 0; i <= 8; ++i) constant.Add(Frame(i), TruePose(i));
  const Pose3 step = *constant.PredictStep(Frame(9));
  EXPECT_LT(TranslationNorm(Between(Between(TruePose(8), TruePose(9)), step)), 1e-4);
}

// from_rest: a first step that erred by 1 cm (the camera moving 3 mm per frame) sets the
// plain prediction for the next frame alone; counting the missing steps as standing still
// keeps a tenth of it; once the history is full both predict the same.
TEST(VelocityHistoryTest, FromRestScalesAShortHistory) {
  const Pose3 jerk = MakePose(Vec3(0.01, 0.0, 0.0), Quat::Identity());
  VelocityHistory plain(10, 0.5), rest(10, 0.5, false, true);
  plain.Add(Frame(0), TruePose(0));
  rest.Add(Frame(0), TruePose(0));
  plain.Add(Frame(1), jerk * TruePose(1));
  rest.Add(Frame(1), jerk * TruePose(1));
  const Pose3 plain_step = *plain.PredictStep(Frame(2));
  const Pose3 rest_step = *rest.PredictStep(Frame(2));
  // Plain: the whole 1 cm error plus the true 3 mm step; from rest: a tenth of that.
  EXPECT_GT(TranslationNorm(plain_step), 0.012);
  EXPECT_NEAR(TranslationNorm(rest_step), 0.1 * TranslationNorm(plain_step), 1e-4);
  for (int i = 2; i <= 12; ++i) {
    plain.Add(Frame(i), TruePose(i));
    rest.Add(Frame(i), TruePose(i));
  }
  const Pose3 truth = Between(TruePose(12), TruePose(13));
  EXPECT_LT(TranslationNorm(Between(truth, *rest.PredictStep(Frame(13)))), 1e-4);
  EXPECT_LT(TranslationNorm(Between(*plain.PredictStep(Frame(13)), *rest.PredictStep(Frame(13)))),
            1e-9);
}

TEST(VelocityHistoryTest, RebaseKeepsThePredictionAndRemovesTheJump) {
  // The poses of frames 0-5 as registered; from frame 6 on they are given in a frame shifted
  // by 4 cm and turned 1 deg (a keyframe whose fused pose differs from its registered one).
  const Pose3 shift =
      MakePose(Vec3(0.04, 0.0, -0.01), Quat(Eigen::AngleAxisd(1.0 * M_PI / 180.0, Vec3::UnitY())));
  VelocityHistory plain(5, 0.5), rebased(5, 0.5);
  for (int i = 0; i <= 5; ++i) {
    plain.Add(Frame(i), TruePose(i));
    rebased.Add(Frame(i), TruePose(i));
  }
  rebased.Rebase(shift);
  const Pose3 before = *plain.PredictStep(Frame(6));
  const Pose3 after = *rebased.PredictStep(Frame(6));
  EXPECT_LT(TranslationNorm(Between(before, after)), 1e-9);
  EXPECT_LT(RotationAngleRad(Between(before, after)), 1e-9);
  VelocityHistory unshifted = plain;
  for (int i = 6; i <= 7; ++i) {
    plain.Add(Frame(i), shift * TruePose(i));
    rebased.Add(Frame(i), shift * TruePose(i));
    unshifted.Add(Frame(i), TruePose(i));
  }
  // Rebased, the history predicts as if nothing had been shifted; without it the shift counts
  // as motion (4 cm over the five steps).
  const Pose3 expected = *unshifted.PredictStep(Frame(8));
  EXPECT_LT(TranslationNorm(Between(expected, *rebased.PredictStep(Frame(8)))), 1e-9);
  EXPECT_GT(TranslationNorm(Between(expected, *plain.PredictStep(Frame(8)))), 0.005);
}

// A hand moves the camera 3 mm per frame (0.09 m/s); at frame 5 the registration follows a
// walker and places the camera 15 cm off (4.5 m/s). Fed as it comes, the spike sets the
// velocity of the next frames (3 cm per frame over five steps); the speed limit sets the step
// aside, the frame keeps the predicted step instead (as the front end does), and the history
// goes on predicting the hand's steps.
TEST(VelocityHistoryTest, SpeedLimitKeepsASpikeOutOfTheHistory) {
  const Pose3 walker = MakePose(Vec3(0.15, 0.0, 0.02), Quat::Identity());
  const auto registered = [&](int i) { return i == 5 ? walker * TruePose(i) : TruePose(i); };
  MotionLimits hand;
  hand.max_speed_mps = 0.5;
  VelocityHistory plain(10, 0.5), gated(10, 0.5);
  Pose3 kept = TruePose(0);  // the gated pose of the frame before
  std::vector<int> rejected;
  for (int i = 0; i <= 8; ++i) {
    plain.Add(Frame(i), registered(i));
    const double dt_s = i > 0 ? DurationSeconds(Frame(i), Frame(i - 1)) : 0.0;
    const std::optional<Pose3> predicted = gated.PredictStep(Frame(i));
    const Status s = CheckHandMotion(Between(kept, registered(i)), dt_s,
                                     predicted ? &*predicted : nullptr, hand);
    if (!s.ok()) {
      rejected.push_back(i);
      EXPECT_NE(s.reason().find("m/s exceeds"), std::string::npos) << s.reason();
    }
    kept = s.ok() ? registered(i) : kept * *predicted;
    gated.Add(Frame(i), kept);
    if (i == 5) {
      EXPECT_GT(TranslationNorm(Between(Between(TruePose(5), TruePose(6)),
                                        *plain.PredictStep(Frame(6)))),
                0.025);
    }
  }
  EXPECT_EQ(rejected, std::vector<int>{5});
  const Pose3 truth = Between(TruePose(8), TruePose(9));
  EXPECT_LT(TranslationNorm(Between(truth, *gated.PredictStep(Frame(9)))), 1e-4);
  // No limit: every step passes.
  EXPECT_TRUE(CheckHandMotion(walker, 1.0 / 30.0, nullptr, MotionLimits()).ok());
  EXPECT_TRUE(WithinSpeed(walker, 0.0, 0.5));
  EXPECT_FALSE(WithinSpeed(walker, 1.0 / 30.0, 0.5));
  EXPECT_TRUE(WithinSpeed(walker, 1.0, 0.5));
  EXPECT_TRUE(WithinSpeed(walker, 1.0 / 30.0, 0.0));
}

// The acceleration limit catches what the speed limit lets through: after steady steps of 3 mm
// per frame, one step of 12 mm (0.36 m/s, under a 0.5 m/s limit) changes the velocity by
// 0.27 m/s within 33 ms (8 m/s^2); a 1 mm change of the step (0.9 m/s^2) passes, and so does
// any step without a prediction to compare with.
TEST(VelocityHistoryTest, AccelerationLimitCatchesASuddenFasterStep) {
  MotionLimits hand;
  hand.max_speed_mps = 0.5;
  hand.max_accel_mps2 = 3.0;
  VelocityHistory h(10, 0.5);
  for (int i = 0; i <= 6; ++i) h.Add(Frame(i), TruePose(i));
  const Pose3 predicted = *h.PredictStep(Frame(7));
  const double dt_s = DurationSeconds(Frame(7), Frame(6));
  const Pose3 truth = Between(TruePose(6), TruePose(7));
  const auto along = [&](double step_m) {
    return MakePose(truth.translation().normalized() * step_m, Quat(truth.rotation()));
  };
  EXPECT_TRUE(CheckHandMotion(truth, dt_s, &predicted, hand).ok());
  const Status fast = CheckHandMotion(along(0.012), dt_s, &predicted, hand);
  EXPECT_FALSE(fast.ok());
  EXPECT_NE(fast.reason().find("velocity change"), std::string::npos) << fast.reason();
  EXPECT_TRUE(
      CheckHandMotion(along(truth.translation().norm() + 0.001), dt_s, &predicted, hand).ok());
  EXPECT_TRUE(CheckHandMotion(along(0.012), dt_s, nullptr, hand).ok());
  // Without the acceleration limit the fast step passes the speed limit.
  hand.max_accel_mps2 = 0.0;
  EXPECT_TRUE(CheckHandMotion(along(0.012), dt_s, &predicted, hand).ok());
}

}  // namespace
}  // namespace icgm
