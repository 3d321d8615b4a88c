#include "core/map/pose_average.h"

#include <gtest/gtest.h>

#include <random>

#include "core/map/se3_geodesic.h"
#include "test_poses.h"

namespace icgm {
namespace {

using test::PoseDistance;
using test::RandomTwist;

const Pose3 kTruth =
    MakePose(Vec3(3.0, -1.0, 0.5), Quat(Eigen::AngleAxisd(1.2, Vec3(0.2, 0.3, 1).normalized())));

TEST(PoseAverageTest, SymmetricHypothesesAverageExactlyToTheCenter) {
  Vec6 e;
  e << 0.2, -0.1, 0.05, 0.1, 0.02, -0.15;
  Pose3 mean;
  ASSERT_TRUE(AveragePoses(
      {{kTruth * GeodesicExp(e), Mat6::Identity()}, {kTruth * GeodesicExp(-e), Mat6::Identity()}},
      &mean));
  EXPECT_LT(PoseDistance(mean, kTruth), 1e-9);
}

TEST(PoseAverageTest, NoisyBetasRecoverTheTruePose) {
  // L_li (+) beta_i = truth (+) noise: 3 earlier loops seen many times.
  std::mt19937 rng(5);
  std::vector<WeightedPose> hypotheses;
  double mean_individual_error = 0.0;
  const int n = 40;
  for (int i = 0; i < n; ++i) {
    const Pose3 loop_pose = MakePose(Vec3(i, 2.0 * i, 0), Quat::Identity());
    const Pose3 beta = loop_pose.inverse() * kTruth * GeodesicExp(RandomTwist(&rng, 0.1, 0.05));
    hypotheses.push_back({loop_pose * beta, Mat6::Identity()});
    mean_individual_error += (hypotheses.back().pose.translation() - kTruth.translation()).norm();
  }
  mean_individual_error /= n;
  Pose3 mean;
  ASSERT_TRUE(AveragePoses(hypotheses, &mean));
  const double error = (mean.translation() - kTruth.translation()).norm();
  EXPECT_LT(error, mean_individual_error / 3.0);
  EXPECT_LT(RotationAngleRad(mean.inverse() * kTruth), 0.05);
}

TEST(PoseAverageTest, InformationWeighsTheHypotheses) {
  const Pose3 far = kTruth * MakePose(Vec3(1.0, 0, 0), Quat::Identity());
  Pose3 mean;
  ASSERT_TRUE(AveragePoses({{kTruth, 99.0 * Mat6::Identity()}, {far, Mat6::Identity()}}, &mean));
  // Weighted mean on the geodesic: 1/100 of the way from kTruth to far.
  EXPECT_NEAR((mean.translation() - kTruth.translation()).norm(), 0.01, 1e-9);
}

TEST(PoseAverageTest, EmptyOrSingularIsAnError) {
  Pose3 mean;
  EXPECT_FALSE(AveragePoses({}, &mean).ok());
  const Status s = AveragePoses({{kTruth, Mat6::Zero()}}, &mean);
  EXPECT_FALSE(s.ok());
  EXPECT_NE(s.reason().find("singular"), std::string::npos);
}

}  // namespace
}  // namespace icgm
