#include "core/nav/loop_follower.h"

#include <gtest/gtest.h>

namespace icgm {
namespace {

std::vector<Pose3> Circle(int n) {
  std::vector<Pose3> poses;
  for (int k = 0; k < n; ++k) {
    const double a = 2 * M_PI * k / n;
    poses.push_back(MakePose(Vec3(5 * std::cos(a), 5 * std::sin(a), 0),
                             Quat(Eigen::AngleAxisd(a + M_PI / 2, Vec3::UnitZ()))));
  }
  return poses;
}

TEST(LoopFollowerTest, MoveReachesModelIPlusOmegaFromTheMeasuredPose) {
  const auto poses = Circle(20);
  LoopFollower follower(poses, 3);
  // Robot near model 4: RelPose_current = its pose in M_4.
  const Pose3 rel = MakePose(Vec3(0.2, -0.1, 0), Quat(Eigen::AngleAxisd(0.15, Vec3::UnitZ())));
  const Pose3 robot = poses[4] * rel;
  Pose3 move;
  ASSERT_TRUE(follower.Step(4, rel, &move));
  EXPECT_LT(((robot * move).matrix() - poses[7].matrix()).norm(), 1e-12);
  EXPECT_EQ(follower.pointer(), 7);
}

TEST(LoopFollowerTest, FailedLoopClosureUsesIdentityAndThePointerReachesTheEnd) {
  const auto poses = Circle(10);
  LoopFollower follower(poses, 4);
  Pose3 move;
  ASSERT_TRUE(follower.Step(0, Pose3::Identity(), &move));
  EXPECT_LT((move.matrix() - Between(poses[0], poses[4]).matrix()).norm(), 1e-12);
  ASSERT_TRUE(follower.Step(4, Pose3::Identity(), &move));
  EXPECT_EQ(follower.pointer(), 8);
  ASSERT_TRUE(follower.Step(8, Pose3::Identity(), &move));  // clamped to N-1
  EXPECT_EQ(follower.pointer(), 9);
  EXPECT_TRUE(follower.done());
  EXPECT_FALSE(follower.Step(8, Pose3::Identity(), &move).ok());
}

TEST(LoopFollowerTest, BadIndexIsAnError) {
  LoopFollower follower(Circle(5), 1);
  Pose3 move;
  const Status s = follower.Step(5, Pose3::Identity(), &move);
  EXPECT_FALSE(s.ok());
  EXPECT_NE(s.reason().find("not in the loop"), std::string::npos);
  EXPECT_FALSE(follower.Step(-1, Pose3::Identity(), &move).ok());
  EXPECT_FALSE(LoopFollower({}, 2).Step(0, Pose3::Identity(), &move).ok());
}

TEST(LoopFollowerTest, LongestLoopOfAMap) {
  HybridMap map;
  int id = -1;
  const Pose3 step = MakePose(Vec3(1, 0, 0), Quat::Identity());
  for (int k = 0; k < 3; ++k) map.AddKeyframe(Keyframe{}, Mat6::Identity(), &id);
  map.StartLoop();
  for (int k = 0; k < 5; ++k) {
    Keyframe kf;
    kf.relative_pose = step;
    map.AddKeyframe(kf, Mat6::Identity(), &id);
  }
  EXPECT_EQ(LoopFollower::LongestLoop(map), (std::vector<int>{3, 4, 5, 6, 7}));
  const LoopFollower f = LoopFollower::FromLongestLoop(map, 2);
  EXPECT_EQ(f.size(), 5);
  EXPECT_TRUE(LoopFollower::LongestLoop(HybridMap()).empty());
}

}  // namespace
}  // namespace icgm
