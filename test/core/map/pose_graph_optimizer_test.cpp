#include "core/map/pose_graph_optimizer.h"

#include <cmath>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "core/map/hybrid_map.h"
#include "test_poses.h"

namespace icgm {
namespace {

using test::PoseDistance;

constexpr int kKeyframes = 40;
constexpr double kRadiusM = 5.0;

Keyframe MakeKeyframe(const Pose3& relative) {
  Keyframe kf;
  kf.relative_pose = relative;
  return kf;
}

Mat6 Information(double sigma_m, double sigma_rad) {
  Mat6 info = Mat6::Zero();
  info.diagonal() << Vec3::Constant(1 / (sigma_m * sigma_m)),
      Vec3::Constant(1 / (sigma_rad * sigma_rad));
  return info;
}

// Ground truth: keyframes on a circle in the xy plane, facing along it; the first at identity.
std::vector<Pose3> CirclePoses() {
  std::vector<Pose3> poses;
  for (int i = 0; i < kKeyframes; ++i) {
    const double a = 2 * M_PI * i / kKeyframes;
    const Vec3 t(kRadiusM * std::sin(a), kRadiusM * (1 - std::cos(a)), 0.1 * std::sin(3 * a));
    poses.push_back(MakePose(t, Quat(Eigen::AngleAxisd(a, Vec3::UnitZ()))));
  }
  return poses;
}

// One session whose odometry links carry a known drift per step (a yaw and a roll bias; a scale
// bias would be unobservable from loop links on a closed circle), plus exact loop links between
// the end and the start of the circle.
HybridMap DriftedLoop(const std::vector<Pose3>& truth) {
  HybridMap map;
  map.StartSession("circle");
  const Pose3 drift = MakePose(Vec3::Zero(), Quat(Eigen::AngleAxisd(0.015, Vec3::UnitZ()) *
                                                  Eigen::AngleAxisd(0.005, Vec3::UnitX())));
  int id = -1;
  for (int i = 0; i < kKeyframes; ++i) {
    const Pose3 relative = i == 0 ? truth[0] : Between(truth[i - 1], truth[i]) * drift;
    EXPECT_TRUE(map.AddKeyframe(MakeKeyframe(relative), Information(0.02, 0.01), &id).ok());
  }
  for (int k = 0; k < 4; ++k) {
    Link link;
    link.from_id = k;
    link.to_id = kKeyframes - 1 - k;
    link.type = LinkType::kLoopClosure;
    link.relative_pose = Between(truth[link.from_id], truth[link.to_id]);
    link.information = Information(0.01, 0.005);
    EXPECT_TRUE(map.AddLink(link).ok());
  }
  return map;
}

double MeanPositionErrorM(const std::vector<Pose3>& poses, const std::vector<Pose3>& truth) {
  double sum = 0.0;
  for (size_t i = 0; i < truth.size(); ++i) {
    sum += (poses[i].translation() - truth[i].translation()).norm();
  }
  return sum / static_cast<double>(truth.size());
}

// False in builds without Ceres, where the optimizer only reports that.
bool BuiltWithCeres() {
  std::vector<Pose3> poses;
  const Status s = PoseGraphOptimizer(PoseGraphOptions()).Optimize(HybridMap(), &poses);
  return s.reason().find("without Ceres") == std::string::npos;
}

std::vector<Pose3> GlobalPoses(const HybridMap& map) {
  std::vector<Pose3> poses;
  for (const auto& kf : map.keyframes()) poses.push_back(kf.global_pose);
  return poses;
}

TEST(PoseGraphOptimizerTest, DriftedCircleIsCorrectedToNearTruth) {
  if (!BuiltWithCeres()) GTEST_SKIP() << "built without Ceres";
  const std::vector<Pose3> truth = CirclePoses();
  const HybridMap map = DriftedLoop(truth);
  const double before_m = MeanPositionErrorM(GlobalPoses(map), truth);
  ASSERT_GT(before_m, 0.5);  // the injected drift is large

  std::vector<Pose3> poses;
  PoseGraphSummary summary;
  const Status s = PoseGraphOptimizer(PoseGraphOptions()).Optimize(map, &poses, &summary);
  ASSERT_TRUE(s.ok()) << s.reason();
  const double after_m = MeanPositionErrorM(poses, truth);
  EXPECT_LT(after_m, 0.1 * before_m) << "before " << before_m << " m, after " << after_m << " m";
  EXPECT_LT(summary.final_cost, summary.initial_cost);
  EXPECT_GT(summary.iterations, 0);
  EXPECT_EQ(summary.residual_blocks, kKeyframes - 1 + 4);
}

TEST(PoseGraphOptimizerTest, FirstKeyframeStaysFixed) {
  if (!BuiltWithCeres()) GTEST_SKIP() << "built without Ceres";
  const std::vector<Pose3> truth = CirclePoses();
  HybridMap map = DriftedLoop(truth);
  // Move the whole map so the fixed pose is not the identity.
  const Pose3 offset = MakePose(Vec3(1, -2, 0.5), Quat(Eigen::AngleAxisd(0.7, Vec3::UnitY())));
  std::vector<Pose3> moved;
  for (const auto& p : GlobalPoses(map)) moved.push_back(offset * p);
  ASSERT_TRUE(map.SetGlobalPoses(moved).ok());

  std::vector<Pose3> poses;
  PoseGraphSummary summary;
  ASSERT_TRUE(PoseGraphOptimizer(PoseGraphOptions()).Optimize(map, &poses, &summary).ok());
  EXPECT_EQ(summary.fixed_keyframes, 1);
  EXPECT_LT(PoseDistance(poses[0], moved[0]), 1e-12);
  EXPECT_GT(PoseDistance(poses.back(), moved.back()), 0.1);  // the rest did move
}

TEST(PoseGraphOptimizerTest, RobustLossLimitsTheDamageOfAWrongLoopLink) {
  if (!BuiltWithCeres()) GTEST_SKIP() << "built without Ceres";
  const std::vector<Pose3> truth = CirclePoses();
  HybridMap map = DriftedLoop(truth);
  Link wrong;  // claims keyframes 10 and 30 (opposite on the circle) are 0.5 m apart
  wrong.from_id = 10;
  wrong.to_id = 30;
  wrong.type = LinkType::kLoopClosure;
  wrong.relative_pose = MakePose(Vec3(0.5, 0.0, 0.0), Quat::Identity());
  wrong.information = Information(0.01, 0.005);
  ASSERT_TRUE(map.AddLink(wrong).ok());

  PoseGraphOptions plain;
  plain.loss = RobustLoss::kNone;
  std::vector<Pose3> poses;
  ASSERT_TRUE(PoseGraphOptimizer(plain).Optimize(map, &poses).ok());
  const double plain_m = MeanPositionErrorM(poses, truth);
  for (const RobustLoss loss_kind : {RobustLoss::kHuber, RobustLoss::kCauchy}) {
    const char* loss = NameOf(loss_kind);
    PoseGraphOptions robust;
    robust.loss = loss_kind;
    const Status s = PoseGraphOptimizer(robust).Optimize(map, &poses);
    ASSERT_TRUE(s.ok()) << loss << ": " << s.reason();
    const double robust_m = MeanPositionErrorM(poses, truth);
    EXPECT_LT(robust_m, 0.5 * plain_m) << loss << ": " << robust_m << " m vs " << plain_m << " m";
  }
}

TEST(PoseGraphOptimizerTest, FailuresAreValuesWithAReason) {
  HybridMap empty;
  std::vector<Pose3> poses;
  Status s = PoseGraphOptimizer(PoseGraphOptions()).Optimize(empty, &poses);
  EXPECT_FALSE(s.ok());
  if (!BuiltWithCeres()) GTEST_SKIP() << "built without Ceres";

  const std::vector<Pose3> truth = CirclePoses();
  const HybridMap map = DriftedLoop(truth);
  PoseGraphOptions one_step;
  one_step.max_iterations = 1;
  one_step.function_tolerance = 0.0;
  s = PoseGraphOptimizer(one_step).Optimize(map, &poses);
  EXPECT_FALSE(s.ok());
  EXPECT_NE(s.reason().find("did not converge"), std::string::npos) << s.reason();
  // On failure the poses are the initial ones.
  EXPECT_LT(PoseDistance(poses.back(), map.keyframes().back().global_pose), 1e-12);
}

TEST(HybridMapSetGlobalPosesTest, RelativePosesFollowTheNewGlobalPoses) {
  const std::vector<Pose3> truth = CirclePoses();
  HybridMap map = DriftedLoop(truth);
  ASSERT_TRUE(map.SetGlobalPoses(truth).ok());
  for (const auto& kf : map.keyframes()) {
    EXPECT_LT(PoseDistance(kf.global_pose, truth[kf.id]), 1e-12);
    const Pose3 parent = kf.previous_id >= 0 ? truth[kf.previous_id] : Pose3::Identity();
    EXPECT_LT(PoseDistance(kf.relative_pose, Between(parent, truth[kf.id])), 1e-9);
  }
  EXPECT_FALSE(map.SetGlobalPoses(std::vector<Pose3>(3)).ok());
}

}  // namespace
}  // namespace icgm
