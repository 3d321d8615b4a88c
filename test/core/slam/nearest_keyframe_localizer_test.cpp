// Localization at the nearest learned keyframes and the odometry fix filter, on a hand-built map:
// keyframes every 0.25 m along x, a synthetic registration that returns the true pose of the
// query in each candidate plus a known error per candidate.
#include "core/slam/nearest_keyframe_localizer.h"

#include <gtest/gtest.h>

#include <map>
#include <set>

namespace icgm {
namespace {

constexpr int kKeyframes = 21;  // x = 0 .. 5 m
constexpr double kStepM = 0.25;

Pose3 AtX(double x, double y = 0.0, double yaw = 0.0) {
  return MakePose(Vec3(x, y, 0.0), Quat(Eigen::AngleAxisd(yaw, Vec3::UnitZ())));
}

Keyframe Model(int stamp_ns, const Pose3& relative) {
  Keyframe kf;
  kf.stamp = Time::FromNanoseconds(stamp_ns);
  kf.descriptors = cv::Mat::zeros(40, 32, CV_8U);
  for (int i = 0; i < 40; ++i) {
    kf.keypoints.emplace_back(static_cast<float>(i), 0.f, 5.f);
    kf.points_m.emplace_back(0.0, 0.0, 1.0);
  }
  kf.relative_pose = relative;
  return kf;
}

class NearestKeyframeTest : public ::testing::Test {
 protected:
  NearestKeyframeTest() {
    int id = -1;
    for (int k = 0; k < kKeyframes; ++k) {
      const Pose3 relative = k == 0 ? AtX(0.0) : AtX(kStepM);
      EXPECT_TRUE(map_.AddKeyframe(Model(k, relative), Mat6::Identity(), &id).ok());
      truth_[k] = AtX(k * kStepM);
    }
  }

  // The query's true pose in candidate k, plus `error_y(k)` sideways; an error when farther apart
  // than 0.5 m. Records which candidates were asked.
  template <typename ErrorFn>
  RegisterFn Registration(const Pose3& query_truth, ErrorFn error_y) {
    return [this, query_truth, error_y](const Keyframe&, const Keyframe& candidate) {
      asked_.insert(candidate.id);
      RegistrationOutcome out;
      const Pose3 relative = Between(truth_.at(candidate.id), query_truth);
      if (TranslationNorm(relative) > 0.5) {
        out.status = Status::Error("registration rejected: 4 inliers < 20");
        return out;
      }
      out.status = Status::Ok();
      out.relative_pose = relative * AtX(0.0, error_y(candidate.id));
      out.inliers = 60;
      out.information = 1.0e4 * Mat6::Identity();
      return out;
    };
  }

  HybridMap map_;
  std::map<int, Pose3> truth_;
  std::set<int> asked_;
};

TEST_F(NearestKeyframeTest, AveragesTheNearestKeyframesHypotheses) {
  const Pose3 truth = AtX(2.1, 0.03, 0.05);
  Keyframe query = Model(100, Pose3::Identity());
  query.global_pose = AtX(2.16, -0.02, 0.02);  // the prediction, 8 cm off
  // Each candidate's registration is 2 cm off sideways, alternating in sign.
  const auto error = [](int id) { return id % 2 == 0 ? 0.02 : -0.02; };
  NearestKeyframeOptions options;
  LoopClosureOptions verification;

  options.count = 1;
  const LoopClosureResult one =
      LocateAtNearestKeyframes(query, map_, kKeyframes, Registration(truth, error), options,
                               verification, FixGateOptions(), 0.5);
  ASSERT_TRUE(one.status.ok()) << one.status.reason();
  ASSERT_EQ(one.evidence.size(), 1u);
  EXPECT_EQ(one.evidence[0].candidate_id, 9);  // x 2.25, nearest to the prediction 2.16
  EXPECT_NEAR(TranslationNorm(Between(truth, one.loop_closure_pose)), 0.02, 1e-6);

  options.count = 4;
  asked_.clear();
  const LoopClosureResult four =
      LocateAtNearestKeyframes(query, map_, kKeyframes, Registration(truth, error), options,
                               verification, FixGateOptions(), 0.5);
  ASSERT_TRUE(four.status.ok()) << four.status.reason();
  EXPECT_EQ(asked_, (std::set<int>{7, 8, 9, 10}));  // x 1.75 .. 2.5: the four nearest
  EXPECT_LT(TranslationNorm(Between(truth, four.loop_closure_pose)), 0.005);

  // Keyframes at or after max_id are not the learned map.
  asked_.clear();
  const LoopClosureResult learned = LocateAtNearestKeyframes(
      query, map_, 9, Registration(truth, error), options, verification, FixGateOptions(), 0.5);
  ASSERT_TRUE(learned.status.ok());
  EXPECT_EQ(asked_, (std::set<int>{5, 6, 7, 8}));
}

TEST_F(NearestKeyframeTest, GuardRejectsWrongRegistrationsAndSaysWhy) {
  const Pose3 truth = AtX(2.0);
  Keyframe query = Model(100, Pose3::Identity());
  query.global_pose = truth;
  NearestKeyframeOptions options;
  options.count = 3;
  LoopClosureOptions verification;
  verification.max_link_translation_m = 10.0;
  // Every registration says 1.5 m sideways: beyond 3 sigma of a fresh fix (0.3 m + 0.1 m/m).
  const LoopClosureResult wrong = LocateAtNearestKeyframes(
      query, map_, kKeyframes, Registration(truth, [](int) { return 1.5; }), options, verification,
      FixGateOptions(), 0.0);
  EXPECT_FALSE(wrong.status.ok());
  EXPECT_NE(wrong.status.reason().find("none of the 3 nearest keyframes"), std::string::npos)
      << wrong.status.reason();
  ASSERT_EQ(wrong.evidence.size(), 3u);
  EXPECT_NE(wrong.evidence[0].rejected.find("jump"), std::string::npos);

  // One wrong, two right: the wrong one is left out of the average.
  const LoopClosureResult mixed = LocateAtNearestKeyframes(
      query, map_, kKeyframes, Registration(truth, [](int id) { return id == 8 ? 1.5 : 0.0; }),
      options, verification, FixGateOptions(), 0.0);
  ASSERT_TRUE(mixed.status.ok());
  EXPECT_LT(TranslationNorm(Between(truth, mixed.loop_closure_pose)), 1e-6);

  // 0.3 m sideways passes the relocalization guard (0.9 m) but not a 0.1 m fix gate.
  FixGateOptions gate;
  gate.max_m = 0.1;
  const LoopClosureResult loose = LocateAtNearestKeyframes(
      query, map_, kKeyframes, Registration(truth, [](int) { return 0.3; }), options, verification,
      FixGateOptions(), 0.0);
  EXPECT_TRUE(loose.status.ok());
  const LoopClosureResult gated = LocateAtNearestKeyframes(
      query, map_, kKeyframes, Registration(truth, [](int) { return 0.3; }), options, verification,
      gate, 0.0);
  EXPECT_FALSE(gated.status.ok());
  EXPECT_NE(gated.status.reason().find("fix gate: jump"), std::string::npos)
      << gated.status.reason();
  // The gate widens with the path since the last fix (0.1 m + 0.05 m/m x 5 m).
  EXPECT_TRUE(LocateAtNearestKeyframes(query, map_, kKeyframes,
                                       Registration(truth, [](int) { return 0.3; }), options,
                                       verification, gate, 5.0)
                  .status.ok());

  // Far from every keyframe (the prediction 3 m beside the line).
  query.global_pose = AtX(2.0, 3.0);
  const LoopClosureResult far = LocateAtNearestKeyframes(
      query, map_, kKeyframes, Registration(truth, [](int) { return 0.0; }), options, verification,
      FixGateOptions(), 0.0);
  EXPECT_FALSE(far.status.ok());
  EXPECT_NE(far.status.reason().find("no learned keyframe near"), std::string::npos);
}

TEST(OdometryFixFilterTest, WeighsThePredictionByThePathSinceTheLastFix) {
  OdometryFixFilterOptions options;
  options.enabled = true;
  OdometryFixFilter filter(options);
  const Mat6 information = 1.0 / (0.01 * 0.01) * Mat6::Identity();  // 1 cm registrations
  // Uninitialized: the measurement is taken as it is.
  const Pose3 first = filter.Update(AtX(0.0), AtX(0.1), information, 0.0);
  EXPECT_NEAR(first.translation().x(), 0.1, 1e-9);
  ASSERT_TRUE(filter.initialized());
  // Short path since the fix: the prediction is as good as the measurement, the fix moves part
  // of the way.
  const Pose3 near = filter.Update(AtX(1.0), AtX(1.03), information, 0.25);
  EXPECT_GT(near.translation().x(), 1.003);
  EXPECT_LT(near.translation().x(), 1.027);
  // A long path since the fix: the odometry has drifted, the measurement dominates.
  OdometryFixFilter after_long(options);
  after_long.Update(AtX(0.0), AtX(0.0), information, 0.0);
  const Pose3 long_path = after_long.Update(AtX(10.0), AtX(10.3), information, 10.0);
  EXPECT_GT(long_path.translation().x(), 10.29);
  // Each fix shrinks the uncertainty below the measurement's own.
  EXPECT_LT(filter.covariance()(0, 0), 0.01 * 0.01);
}

}  // namespace
}  // namespace icgm
