// The split of a monocular run's error over its maps, on a hand-built run with a known ground
// truth: a bent path cut into two maps whose scales differ, as after a re-initialization that
// carried the scale wrongly.
#include <algorithm>
#include <cmath>
#include <vector>

#include <gtest/gtest.h>
#include <Eigen/Geometry>

#include "core/mono/mono_evaluation.h"

namespace icgm {
namespace {

constexpr size_t kPoses = 200;

Time StampOf(size_t i) { return Time::FromSeconds(10.0 + i / 30.0); }

// A bent, rising path (never collinear, so every part aligns with Sim(3)).
Eigen::Vector3d TruthAt(size_t i) {
  const double a = 0.01 * i;
  return Eigen::Vector3d(2.0 * std::sin(a), 0.3 * a, 2.0 * (1.0 - std::cos(a)));
}

Trajectory Truth() {
  Trajectory t;
  for (size_t i = 0; i < kPoses; ++i) {
    Pose3 p = Pose3::Identity();
    p.translation() = TruthAt(i);
    t.push_back({StampOf(i), p});
  }
  return t;
}

// Map 0: poses 0..cut at 1 / scale0 units per metre; map 1: its reference is pose `cut` (the
// same stamp as map 0's last), then poses cut+1.. with steps at 1 / scale1 units per metre; the
// whole of map 1 is shifted by `jump` (map units).
std::vector<Trajectory> TwoMaps(size_t cut, double scale0, double scale1,
                                const Eigen::Vector3d& jump) {
  std::vector<Trajectory> maps(2);
  Eigen::Vector3d p = TruthAt(0) / scale0;
  for (size_t i = 0; i < kPoses; ++i) {
    if (i > 0) p += (TruthAt(i) - TruthAt(i - 1)) / (i <= cut ? scale0 : scale1);
    Pose3 pose = Pose3::Identity();
    pose.translation() = p;
    if (i <= cut) maps[0].push_back({StampOf(i), pose});
    pose.translation() += jump;
    if (i >= cut) maps[1].push_back({StampOf(i), pose});
  }
  return maps;
}

TEST(MonoEvaluationTest, ScaleJumpBetweenMapsIsSeparatedFromTheRest) {
  // 2 m per unit, then 0.5 m per unit: a four-fold scale jump at pose 100.
  MonoMapBreakdown split;
  const Status s =
      BreakDownMonoMaps(Truth(), TwoMaps(100, 2.0, 0.5, Eigen::Vector3d::Zero()), 0.01, &split);
  ASSERT_TRUE(s.ok()) << s.reason();
  ASSERT_EQ(split.maps.size(), 2u);
  EXPECT_EQ(split.aligned_maps, 2u);
  EXPECT_NEAR(split.maps[0].scale, 2.0, 1e-6);
  EXPECT_NEAR(split.maps[1].scale, 0.5, 1e-6);
  EXPECT_EQ(split.maps[0].poses, 101u);
  EXPECT_EQ(split.maps[1].poses, 100u);
  // One Sim(3) cannot fit both scales; rescaled by the truth's scales the run is exact, and each
  // map alone is exact.
  EXPECT_GT(split.whole_percent, 1.0);
  EXPECT_LT(split.scale_fixed_percent, 1e-6);
  EXPECT_LT(split.per_map_percent, 1e-6);
  // The local scales at the reset show the same jump, and carrying them removes it too.
  EXPECT_NEAR(split.maps[0].scale_last, 2.0, 1e-6);
  EXPECT_NEAR(split.maps[1].scale_first, 0.5, 1e-6);
  EXPECT_LT(split.carry_fixed_percent, 1e-6);
}

TEST(MonoEvaluationTest, PositionJumpStaysAfterTheScalesAreMadeEqual) {
  // The same scale in both maps, but map 1 starts 0.2 units off (the motion during lost frames
  // that the new map did not see): the scale correction leaves that error, each map alone has
  // none.
  MonoMapBreakdown split;
  const Status s = BreakDownMonoMaps(
      Truth(), TwoMaps(100, 2.0, 2.0, Eigen::Vector3d(0.2, 0.0, 0.0)), 0.01, &split);
  ASSERT_TRUE(s.ok()) << s.reason();
  EXPECT_NEAR(split.maps[1].scale, 2.0, 1e-6);
  EXPECT_GT(split.whole_percent, 1.0);
  EXPECT_NEAR(split.scale_fixed_percent, split.whole_percent, 1e-9);
  EXPECT_NEAR(split.carry_fixed_percent, split.whole_percent, 1e-9);
  EXPECT_LT(split.per_map_percent, 1e-6);
}

TEST(MonoEvaluationTest, ShortMapKeepsTheFactorOfTheMapBefore) {
  // A 5-pose map between two aligned ones cannot be aligned on its own; it is neither counted
  // in the per-map error nor given a scale, and the run still splits.
  std::vector<Trajectory> maps = TwoMaps(100, 2.0, 0.5, Eigen::Vector3d::Zero());
  Trajectory short_map(maps[1].begin(), maps[1].begin() + 5);
  maps[1].erase(maps[1].begin(), maps[1].begin() + 4);
  maps.insert(maps.begin() + 1, short_map);
  MonoMapBreakdown split;
  const Status s = BreakDownMonoMaps(Truth(), maps, 0.01, &split);
  ASSERT_TRUE(s.ok()) << s.reason();
  ASSERT_EQ(split.maps.size(), 3u);
  EXPECT_FALSE(split.maps[1].aligned);
  EXPECT_EQ(split.aligned_maps, 2u);
  // The short map's 4 steps keep map 0's factor (1) though they are at 0.5 m per unit: some
  // error is left, far less than without the correction.
  EXPECT_GT(split.scale_fixed_percent, 0.0);
  EXPECT_LT(split.scale_fixed_percent, 0.5 * split.whole_percent);
  EXPECT_LT(split.per_map_percent, 1e-6);
}


// The joins between maps, each on its own: a four-fold scale jump shows as that ratio and
// nothing else, and moving every map onto the one before at its join leaves no error.
TEST(MonoEvaluationTest, JoinShowsItsScaleJump) {
  MonoMapBreakdown split;
  const Status s =
      BreakDownMonoMaps(Truth(), TwoMaps(100, 2.0, 0.5, Eigen::Vector3d::Zero()), 0.01, &split);
  ASSERT_TRUE(s.ok()) << s.reason();
  ASSERT_EQ(split.joins.size(), 1u);
  const MonoJoinFigures& j = split.joins[0];
  EXPECT_TRUE(j.aligned);
  EXPECT_EQ(j.map, 1u);
  EXPECT_NEAR(j.scale_ratio, 0.25, 1e-6);
  EXPECT_NEAR(j.rotation_deg, 0.0, 1e-6);
  EXPECT_NEAR(j.position_m, 0.0, 1e-6);
  EXPECT_NEAR(j.gap_s, 0.0, 1e-9);
  EXPECT_GT(split.whole_percent, 1.0);
  EXPECT_LT(split.joins_fixed_percent, 1e-6);
  // Rotation and position alone cannot remove a scale jump.
  EXPECT_GT(split.joins_rigid_fixed_percent, 1.0);
}

// Map 1 turned by 10 degrees about its reference frame (the orientation a re-initialization
// lost): the join shows the angle and no position error there; the scales agree.
TEST(MonoEvaluationTest, JoinShowsTheOrientationItLost) {
  std::vector<Trajectory> maps = TwoMaps(100, 2.0, 2.0, Eigen::Vector3d::Zero());
  const Eigen::Vector3d centre = maps[1].front().pose.translation();
  const Eigen::Matrix3d turn =
      Eigen::AngleAxisd(10.0 * M_PI / 180.0, Eigen::Vector3d(0.2, 1.0, 0.3).normalized())
          .toRotationMatrix();
  for (StampedPose& p : maps[1]) {
    p.pose.translation() = centre + turn * (p.pose.translation() - centre);
    p.pose.linear() = turn * p.pose.linear();
  }
  MonoMapBreakdown split;
  const Status s = BreakDownMonoMaps(Truth(), maps, 0.01, &split);
  ASSERT_TRUE(s.ok()) << s.reason();
  ASSERT_EQ(split.joins.size(), 1u);
  EXPECT_NEAR(split.joins[0].rotation_deg, 10.0, 1e-6);
  EXPECT_NEAR(split.joins[0].scale_ratio, 1.0, 1e-6);
  EXPECT_NEAR(split.joins[0].position_m, 0.0, 1e-6);
  // The scale correction cannot remove a turn; moving the map onto the one before can.
  EXPECT_GT(split.carry_fixed_percent, 0.5);
  EXPECT_LT(split.joins_fixed_percent, 1e-6);
  EXPECT_LT(split.joins_rigid_fixed_percent, 1e-6);
  EXPECT_LT(split.per_map_percent, 1e-6);
}

// A reset after which frames 101-109 got no pose, and the new map's reference frame (frame 110)
// was placed at the last tracked pose: the join misses the truth's motion over the gap.
TEST(MonoEvaluationTest, JoinShowsTheMotionOverFramesWithoutPose) {
  const Trajectory truth = Truth();
  std::vector<Trajectory> maps(2);
  for (size_t i = 0; i <= 100; ++i) maps[0].push_back(truth[i]);
  const Eigen::Vector3d lost = truth[110].pose.translation() - truth[100].pose.translation();
  for (size_t i = 110; i < kPoses; ++i) {
    StampedPose p = truth[i];
    p.pose.translation() -= lost;
    maps[1].push_back(p);
  }
  MonoMapBreakdown split;
  const Status s = BreakDownMonoMaps(truth, maps, 0.01, &split);
  ASSERT_TRUE(s.ok()) << s.reason();
  ASSERT_EQ(split.joins.size(), 1u);
  const MonoJoinFigures& j = split.joins[0];
  EXPECT_NEAR(j.gap_s, 10.0 / 30.0, 1e-6);
  EXPECT_NEAR(j.gap_motion_m, lost.norm(), 1e-9);
  EXPECT_NEAR(j.position_m, lost.norm(), 1e-6);
  EXPECT_NEAR(j.scale_ratio, 1.0, 1e-6);
  EXPECT_GT(split.whole_percent, 1.0);
  EXPECT_LT(split.joins_fixed_percent, 1e-6);
  EXPECT_LT(split.joins_rigid_fixed_percent, 1e-6);
}

// The truth with its camera turning along the path (yaw a about the vertical axis), so the
// segments' relative poses carry orientations.
Trajectory TurningTruth() {
  Trajectory t = Truth();
  for (size_t i = 0; i < t.size(); ++i) {
    t[i].pose.linear() = Eigen::AngleAxisd(0.01 * i, Eigen::Vector3d::UnitY()).toRotationMatrix();
  }
  return t;
}

// `estimate` moved by the similarity (scale, rotation, offset) a monocular map is free in.
Trajectory InMapUnits(const Trajectory& truth, double units_per_m) {
  const Eigen::Matrix3d r =
      Eigen::AngleAxisd(0.7, Eigen::Vector3d(1.0, 2.0, 0.5).normalized()).toRotationMatrix();
  Trajectory e = truth;
  for (StampedPose& p : e) {
    p.pose.linear() = r * p.pose.linear();
    p.pose.translation() = units_per_m * (r * p.pose.translation()) + Eigen::Vector3d(3, -1, 2);
  }
  return e;
}

TEST(MonoEvaluationTest, SegmentErrorOfTheTruthInMapUnitsIsZero) {
  MonoEvaluation eval;
  ASSERT_TRUE(
      EvaluateMonoTrajectory(TurningTruth(), InMapUnits(TurningTruth(), 0.4), 0.01, &eval).ok());
  MonoSegmentErrors segments;
  const Status s = EvaluateMonoSegments(eval.evaluation, DefaultSegmentFractions(), &segments);
  ASSERT_TRUE(s.ok()) << s.reason();
  ASSERT_EQ(segments.lengths.size(), 5u);
  // Longer segments leave fewer starts; every start whose segment ends inside the run counts.
  EXPECT_GT(segments.lengths[0].segments, segments.lengths[4].segments);
  EXPECT_GT(segments.lengths[4].segments, 50u);
  EXPECT_NEAR(segments.lengths[2].length_m, 0.3 * eval.distance_m, 1e-9);
  EXPECT_LT(segments.mean_percent, 1e-6);
  // The helix's chord over its arc: standing still scores just under 100 %.
  EXPECT_GT(segments.standing_still_percent, 80.0);
  EXPECT_LT(segments.standing_still_percent, 100.0);
  EXPECT_FALSE(EvaluateMonoSegments(eval.evaluation, {0.0}, &segments).ok());
  EXPECT_FALSE(EvaluateMonoSegments(eval.evaluation, {1.0}, &segments).ok());
}

// The parts of the segment error: the truth in map units has none; orientations turned by a
// fixed 10 deg in the camera (a wrong camera mounting) leave every displacement's length exact
// (ratio 1, no length error) and turn its direction by at most 10 deg in the first pose's frame.
TEST(MonoEvaluationTest, SegmentPartsSeparateDirectionFromLength) {
  MonoEvaluation eval;
  MonoSegmentErrors exact;
  ASSERT_TRUE(
      EvaluateMonoTrajectory(TurningTruth(), InMapUnits(TurningTruth(), 0.4), 0.01, &eval).ok());
  ASSERT_TRUE(EvaluateMonoSegments(eval.evaluation, DefaultSegmentFractions(), &exact).ok());
  EXPECT_LT(exact.rotation_error_deg, 1e-6);
  EXPECT_LT(exact.direction_error_deg, 1e-3);
  EXPECT_NEAR(exact.length_ratio_median, 1.0, 1e-9);
  EXPECT_LT(exact.length_only_percent, 1e-6);

  Trajectory mounted = TurningTruth();
  const Eigen::Matrix3d offset =
      Eigen::AngleAxisd(10.0 * M_PI / 180.0, Eigen::Vector3d(1.0, 0.5, 0.0).normalized())
          .toRotationMatrix();
  for (StampedPose& p : mounted) p.pose.linear() = p.pose.linear() * offset;
  ASSERT_TRUE(EvaluateMonoTrajectory(TurningTruth(), InMapUnits(mounted, 0.4), 0.01, &eval).ok());
  MonoSegmentErrors turned;
  ASSERT_TRUE(EvaluateMonoSegments(eval.evaluation, DefaultSegmentFractions(), &turned).ok());
  EXPECT_NEAR(turned.length_ratio_median, 1.0, 1e-9);
  EXPECT_LT(turned.length_only_percent, 1e-6);
  EXPECT_GT(turned.direction_error_deg, 1.0);
  EXPECT_LT(turned.direction_error_deg, 10.0 + 1e-6);
  EXPECT_GT(turned.rotation_error_deg, 0.1);
  // The displacement turned by up to 10 deg: an error of up to 2 sin 5 deg = 17 % of its length.
  EXPECT_GT(turned.mean_percent, 1.0);
  EXPECT_LT(turned.mean_percent, 17.5);
}

// A heading error of 20 deg at frame 100 (the rest of the run turned about that frame's
// position, as after a wrong rotation at a re-initialization): the whole-run ATE carries it
// into every later pose, a segment only when it spans frame 100.
TEST(MonoEvaluationTest, HeadingJumpCountsOnlyInTheSegmentsSpanningIt) {
  const Trajectory truth = TurningTruth();
  Trajectory bent = truth;
  const Eigen::Matrix3d turn =
      Eigen::AngleAxisd(20.0 * M_PI / 180.0, Eigen::Vector3d::UnitY()).toRotationMatrix();
  const Eigen::Vector3d pivot = truth[100].pose.translation();
  for (size_t i = 101; i < bent.size(); ++i) {
    bent[i].pose.linear() = turn * truth[i].pose.linear();
    bent[i].pose.translation() = pivot + turn * (truth[i].pose.translation() - pivot);
  }
  MonoEvaluation eval;
  ASSERT_TRUE(EvaluateMonoTrajectory(truth, InMapUnits(bent, 2.5), 0.01, &eval).ok());
  MonoSegmentErrors segments;
  ASSERT_TRUE(EvaluateMonoSegments(eval.evaluation, {0.1}, &segments).ok());
  // The run's one scale fits the bent shape, not exactly the truth's (3 % off): the segments
  // that do not span frame 100 share about one error, that scale's; the 20 deg adds at least
  // 1.7 points (2 sin 10 deg of one step of the 20 in a segment) to those that span it.
  const double least =
      *std::min_element(segments.errors_percent.begin(), segments.errors_percent.end());
  EXPECT_LT(least, 5.0);
  size_t exact = 0;
  for (const double e : segments.errors_percent) exact += e < least + 0.5 ? 1 : 0;
  // About 20 of the 180 segments of a tenth of the path span frame 100.
  EXPECT_GT(exact, segments.errors_percent.size() * 8 / 10);
  EXPECT_LT(exact, segments.errors_percent.size());
  EXPECT_GT(eval.error_percent, 1.0);
}

}  // namespace
}  // namespace icgm
