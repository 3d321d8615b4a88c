#include "core/map/hybrid_map.h"

#include <gtest/gtest.h>

#include "core/map/se3_geodesic.h"
#include "test_poses.h"

namespace icgm {
namespace {

using test::PoseDistance;

Keyframe MakeKeyframe(const Pose3& relative, int features = 3) {
  Keyframe kf;
  kf.relative_pose = relative;
  for (int i = 0; i < features; ++i) {
    kf.keypoints.emplace_back(10.f * i, 5.f, 7.f);
    kf.points_m.emplace_back(0.1 * i, 0.0, 2.0);
  }
  kf.descriptors = cv::Mat(features, 32, CV_8U, cv::Scalar(7));
  return kf;
}

const Pose3 kStep = MakePose(Vec3(1.0, 0.0, 0.0), Quat(Eigen::AngleAxisd(0.1, Vec3::UnitZ())));

TEST(HybridMapTest, GlobalPosesFollowEq61AndOdometryLinksChain) {
  HybridMap map;
  int id = -1;
  for (int k = 0; k < 5; ++k)
    ASSERT_TRUE(map.AddKeyframe(MakeKeyframe(kStep), Mat6::Identity(), &id));
  EXPECT_EQ(id, 4);
  Pose3 expected = Pose3::Identity();
  for (int k = 0; k < 5; ++k) {
    expected = expected * kStep;
    EXPECT_LT(PoseDistance(map.keyframe(k).global_pose, expected), 1e-12);
    EXPECT_EQ(map.keyframe(k).previous_id, k - 1);
  }
  EXPECT_EQ(map.keyframe(0).relative_source, RelativePoseSource::kSessionStart);
  ASSERT_EQ(map.links().size(), 4u);
  EXPECT_EQ(map.links()[3].from_id, 3);
  EXPECT_EQ(map.links()[3].to_id, 4);
  EXPECT_NEAR(map.PathLengthSinceCorrectionM(), 5.0, 1e-12);
  EXPECT_TRUE(map.Validate());
}

TEST(HybridMapTest, LoopsPartitionKeyframesAndTheChainContinues) {
  HybridMap map;
  int id = -1;
  map.StartSession("day");
  for (int k = 0; k < 3; ++k) map.AddKeyframe(MakeKeyframe(kStep), Mat6::Identity(), &id);
  const int second = map.StartLoop();
  EXPECT_EQ(second, 1);
  EXPECT_EQ(map.StartLoop(), 1);  // an empty loop is reused
  for (int k = 0; k < 2; ++k) map.AddKeyframe(MakeKeyframe(kStep), Mat6::Identity(), &id);
  EXPECT_EQ(map.loops()[0].keyframe_ids, (std::vector<int>{0, 1, 2}));
  EXPECT_EQ(map.loops()[1].keyframe_ids, (std::vector<int>{3, 4}));
  EXPECT_EQ(map.keyframe(3).previous_id, 2);
  EXPECT_EQ(map.keyframe(3).loop_id, 1);
}

TEST(HybridMapTest, SemiConsensusMovesTheLatestPoseAndSetsTheAnchor) {
  HybridMap map;
  int id = -1;
  for (int k = 0; k < 10; ++k) map.AddKeyframe(MakeKeyframe(kStep), Mat6::Identity(), &id);
  const Pose3 before = map.keyframe(9).global_pose;
  const Pose3 target = before * MakePose(Vec3(0.5, -0.3, 0.0), Quat::Identity());
  ASSERT_TRUE(map.ApplySemiConsensus(9, target, 0.5));
  const Vec6 xi = GeodesicLog(target * before.inverse());
  EXPECT_LT((GeodesicLog(map.keyframe(9).global_pose * before.inverse()) - 0.5 * xi).norm(), 1e-9);
  EXPECT_EQ(map.sessions()[0].last_corrected_id, 9);
  EXPECT_NEAR(map.PathLengthSinceCorrectionM(), 0.0, 1e-12);
  // The next correction only spreads over keyframes after the anchor.
  for (int k = 0; k < 4; ++k) map.AddKeyframe(MakeKeyframe(kStep), Mat6::Identity(), &id);
  const Pose3 anchor = map.keyframe(9).global_pose;
  const Pose3 target2 = map.keyframe(13).global_pose * kStep;
  ASSERT_TRUE(map.ApplySemiConsensus(13, target2, 1.0));
  EXPECT_LT(PoseDistance(map.keyframe(9).global_pose, anchor), 1e-12);
  EXPECT_LT(PoseDistance(map.keyframe(13).global_pose, target2), 1e-9);  // alpha = 1: consensus
  // Only the latest keyframe of the current session can be corrected.
  EXPECT_FALSE(map.ApplySemiConsensus(5, target, 0.5).ok());
  EXPECT_FALSE(map.ApplySemiConsensus(13, target, 1.5).ok());
}

TEST(HybridMapTest, MismatchedKeyframeIsRejectedWithReason) {
  HybridMap map;
  Keyframe kf = MakeKeyframe(kStep);
  kf.points_m.pop_back();
  int id = -1;
  const Status s = map.AddKeyframe(kf, Mat6::Identity(), &id);
  EXPECT_FALSE(s.ok());
  EXPECT_NE(s.reason().find("3D points"), std::string::npos);
  EXPECT_TRUE(map.empty());
  Link bad;
  bad.from_id = 0;
  bad.to_id = 7;
  EXPECT_FALSE(map.AddLink(bad).ok());
}

TEST(HybridMapTest, MergeRenumbersAndKeepsSessions) {
  HybridMap a;
  HybridMap b;
  int id = -1;
  a.StartSession("morning");
  for (int k = 0; k < 3; ++k) a.AddKeyframe(MakeKeyframe(kStep), Mat6::Identity(), &id);
  b.StartSession("evening");
  for (int k = 0; k < 4; ++k) b.AddKeyframe(MakeKeyframe(kStep), Mat6::Identity(), &id);
  b.StartLoop();
  b.AddKeyframe(MakeKeyframe(kStep), Mat6::Identity(), &id);
  Link loop;
  loop.from_id = 0;
  loop.to_id = 4;
  loop.type = LinkType::kLoopClosure;
  ASSERT_TRUE(b.AddLink(loop));
  const Pose3 offset = MakePose(Vec3(0, 0, 1), Quat::Identity());
  a.Merge(b, offset);
  ASSERT_EQ(a.size(), 8);
  ASSERT_EQ(a.sessions().size(), 2u);
  EXPECT_EQ(a.sessions()[1].name, "evening");
  EXPECT_EQ(a.loops().size(), 3u);
  EXPECT_EQ(a.keyframe(3).session_id, 1);
  EXPECT_EQ(a.keyframe(3).previous_id, -1);
  EXPECT_EQ(a.keyframe(4).previous_id, 3);
  EXPECT_EQ(a.keyframe(7).loop_id, 2);
  EXPECT_LT(PoseDistance(a.keyframe(3).global_pose, offset * b.keyframe(0).global_pose), 1e-12);
  EXPECT_EQ(a.links().back().from_id, 3);
  EXPECT_EQ(a.links().back().to_id, 7);
  EXPECT_TRUE(a.Validate());
  // New keyframes still extend the first map's current session.
  a.AddKeyframe(MakeKeyframe(kStep), Mat6::Identity(), &id);
  EXPECT_EQ(a.keyframe(id).previous_id, 2);
}

}  // namespace
}  // namespace icgm
