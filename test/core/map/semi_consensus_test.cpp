#include "core/map/semi_consensus.h"

#include <gtest/gtest.h>

#include <random>
#include <vector>

#include "core/map/se3_geodesic.h"
#include "test_poses.h"

namespace icgm {
namespace {

using test::PoseDistance;
using test::RandomTwist;

TEST(GeodesicTest, ExpLogRoundTripAndOneParameterSubgroup) {
  std::mt19937 rng(3);
  for (int i = 0; i < 50; ++i) {
    const Vec6 xi = RandomTwist(&rng, 2.0, 0.8);
    EXPECT_LT((GeodesicLog(GeodesicExp(xi)) - xi).norm(), 1e-9);
    // Exp(s xi) Exp(t xi) = Exp((s + t) xi): what splitting a difference into increments needs.
    const Pose3 a = GeodesicExp(0.3 * xi) * GeodesicExp(0.5 * xi);
    EXPECT_LT(PoseDistance(a, GeodesicExp(0.8 * xi)), 1e-9);
  }
  Vec6 tiny = Vec6::Zero();
  tiny << 1, 2, 3, 1e-9, 0, 0;
  EXPECT_LT((GeodesicExp(tiny).translation() - Vec3(1, 2, 3)).norm(), 1e-8);
}

// A square drive of 4 x 10 keyframes; the drifted chain carries a per-step error.
struct Chain {
  std::vector<Pose3> truth;     // L_1 .. L_n
  std::vector<Pose3> relative;  // drifted R_1 .. R_n
};

Chain MakeDriftedSquare(const Pose3& world_drift_step) {
  Chain c;
  Pose3 pose = Pose3::Identity();
  Pose3 drifted = Pose3::Identity();
  Pose3 drift = Pose3::Identity();
  for (int k = 1; k <= 40; ++k) {
    Pose3 step = MakePose(Vec3(0.5, 0, 0), Quat::Identity());
    if (k % 10 == 0)
      step = MakePose(Vec3(0.5, 0, 0), Quat(Eigen::AngleAxisd(M_PI / 2, Vec3::UnitZ())));
    pose = pose * step;
    c.truth.push_back(pose);
    // Drifted pose = drift^k * truth: a uniform world-frame error per keyframe.
    drift = world_drift_step * drift;
    const Pose3 new_drifted = drift * pose;
    c.relative.push_back(drifted.inverse() * new_drifted);
    drifted = new_drifted;
  }
  return c;
}

std::vector<Pose3> Rebuild(const Pose3& start, const std::vector<Pose3>& relative) {
  std::vector<Pose3> out;
  Pose3 p = start;
  for (const auto& r : relative) out.push_back(p = p * r);
  return out;
}

TEST(SemiConsensusTest, MovesLastPoseByExactlyAlphaOfTheDifference) {
  Vec6 d;
  d << 0.01, -0.02, 0.005, 0.001, -0.002, 0.004;
  const Chain c = MakeDriftedSquare(GeodesicExp(d));
  const std::vector<Pose3> before = Rebuild(Pose3::Identity(), c.relative);
  const Pose3 loop_closure = c.truth.back();
  const Vec6 xi = GeodesicLog(loop_closure * before.back().inverse());
  for (double alpha : {0.25, 0.5, 0.8}) {
    const auto after =
        Rebuild(Pose3::Identity(),
                SemiConsensusCorrection(Pose3::Identity(), c.relative, loop_closure, alpha));
    // L'_b = Exp(alpha xi) L_b exactly.
    EXPECT_LT((GeodesicLog(after.back() * before.back().inverse()) - alpha * xi).norm(), 1e-9)
        << alpha;
    // What remains is exactly (1 - alpha) of the difference.
    EXPECT_LT((GeodesicLog(loop_closure * after.back().inverse()) - (1 - alpha) * xi).norm(), 1e-9);
    EXPECT_LT(PoseDistance(after.back(), loop_closure), PoseDistance(before.back(), loop_closure));
  }
}

TEST(SemiConsensusTest, FullConsensusRecoversUniformDriftEverywhere) {
  Vec6 d;
  d << 0.02, 0.01, -0.01, 0.0, 0.001, 0.003;
  const Chain c = MakeDriftedSquare(GeodesicExp(d));
  const std::vector<Pose3> before = Rebuild(Pose3::Identity(), c.relative);
  const auto after =
      Rebuild(Pose3::Identity(),
              SemiConsensusCorrection(Pose3::Identity(), c.relative, c.truth.back(), 1.0));
  double error_before = 0.0;
  for (size_t k = 0; k < c.truth.size(); ++k) {
    error_before += (before[k].translation() - c.truth[k].translation()).norm();
    // Drift grows linearly in the world frame, so the linear ramp undoes it at every keyframe.
    EXPECT_LT(PoseDistance(after[k], c.truth[k]), 1e-8) << k;
  }
  EXPECT_GT(error_before, 1.0);
}

TEST(SemiConsensusTest, RandomDriftIsReducedAlongTheChainAndAnchorStays) {
  std::mt19937 rng(11);
  Chain c = MakeDriftedSquare(Pose3::Identity());
  for (auto& r : c.relative) r = r * GeodesicExp(RandomTwist(&rng, 0.01, 0.004));
  const Pose3 anchor = MakePose(Vec3(1, 2, 0), Quat(Eigen::AngleAxisd(0.3, Vec3::UnitZ())));
  std::vector<Pose3> truth;
  for (const auto& t : c.truth) truth.push_back(anchor * t);
  const auto before = Rebuild(anchor, c.relative);
  const auto corrected = SemiConsensusCorrection(anchor, c.relative, truth.back(), 0.5);
  ASSERT_EQ(corrected.size(), c.relative.size());
  const auto after = Rebuild(anchor, corrected);
  double sum_before = 0.0;
  double sum_after = 0.0;
  for (size_t k = 0; k < truth.size(); ++k) {
    sum_before += (before[k].translation() - truth[k].translation()).norm();
    sum_after += (after[k].translation() - truth[k].translation()).norm();
  }
  EXPECT_LT(sum_after, sum_before);
  EXPECT_LT(PoseDistance(after.back(), truth.back()), PoseDistance(before.back(), truth.back()));
}

// Eq. 6.4 on a loop worked by hand. From L_a = I (a = 0) the chain drives 1 m along x, turns
// left by 90 deg and drives on (b = 4):
//   R_1 = (1, 0, 0);  R_2 = (1, 0, 0) then yaw +90 deg;  R_3 = R_4 = (1, 0, 0)
//   L_1 = (1, 0), L_2 = (2, 0) yaw 90, L_3 = (2, 1) yaw 90, L_4 = (2, 2) yaw 90.
// The loop closure puts model 4 at L_LC = (2.4, 1.8) yaw 90, so eq. 6.3's difference is the
// world translation D = L_LC L_4^-1 = (0.4, -0.2, 0). With alpha = 0.5 and b - a = 4 every
// relative pose gets delta = 0.5 / 4 * (0.4, -0.2) = (0.05, -0.025) in the world frame, i.e.
// R'_k = L_(k-1)^-1 delta L_(k-1) R_k: delta seen from L_(k-1)'s heading.
//   R'_1 = (1.05, -0.025)                     (L_0 heads along x: delta as is)
//   R'_2 = (1.05, -0.025) then yaw +90 deg    (L_1 heads along x)
//   R'_3 = R'_4 = (1 - 0.025, -0.05) = (0.975, -0.05)   (L_2, L_3 head along y: delta turned
//                                                        by -90 deg is (-0.025, -0.05))
// Rebuilt (eq. 6.1): L'_k = L_k + k delta: (1.05, -0.025), (2.1, -0.05), (2.15, 0.925),
// (2.2, 1.9); L'_4 lies halfway from L_4 = (2, 2) to L_LC = (2.4, 1.8) (semi-consensus).
TEST(SemiConsensusTest, WorkedLoopWithATurn) {
  const Quat left(Eigen::AngleAxisd(M_PI / 2, Vec3::UnitZ()));
  const Pose3 forward = MakePose(Vec3(1, 0, 0), Quat::Identity());
  const std::vector<Pose3> relative{forward, MakePose(Vec3(1, 0, 0), left), forward, forward};
  const Pose3 loop_closure = MakePose(Vec3(2.4, 1.8, 0), left);
  const std::vector<Pose3> corrected =
      SemiConsensusCorrection(Pose3::Identity(), relative, loop_closure, 0.5);
  ASSERT_EQ(corrected.size(), 4u);
  const Vec3 expected_relative[4] = {
      {1.05, -0.025, 0}, {1.05, -0.025, 0}, {0.975, -0.05, 0}, {0.975, -0.05, 0}};
  const double expected_yaw[4] = {0, M_PI / 2, 0, 0};
  for (int k = 0; k < 4; ++k) {
    EXPECT_LT((corrected[k].translation() - expected_relative[k]).norm(), 1e-12) << "R'_" << k + 1;
    EXPECT_NEAR(RotationAngleRad(corrected[k]), expected_yaw[k], 1e-12) << "R'_" << k + 1;
  }
  const std::vector<Pose3> rebuilt = Rebuild(Pose3::Identity(), corrected);
  const Vec3 expected_global[4] = {
      {1.05, -0.025, 0}, {2.1, -0.05, 0}, {2.15, 0.925, 0}, {2.2, 1.9, 0}};
  for (int k = 0; k < 4; ++k) {
    EXPECT_LT((rebuilt[k].translation() - expected_global[k]).norm(), 1e-12) << "L'_" << k + 1;
  }
  EXPECT_LT(PoseDistance(rebuilt[3], MakePose(Vec3(2.2, 1.9, 0), left)), 1e-12);
}

TEST(SemiConsensusTest, ZeroAlphaChangesNothing) {
  const Chain c = MakeDriftedSquare(GeodesicExp(Vec6::Constant(0.01)));
  const auto corrected =
      SemiConsensusCorrection(Pose3::Identity(), c.relative, c.truth.back(), 0.0);
  for (size_t k = 0; k < corrected.size(); ++k) {
    EXPECT_LT(PoseDistance(corrected[k], c.relative[k]), 1e-12);
  }
}

}  // namespace
}  // namespace icgm
