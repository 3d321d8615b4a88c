// People removal on a constructed case: three keyframes side by side look at a wall 4 m away;
// the first also sees a person 2 m in front of it, who has left when the others look. The
// person's points are seen through by the other keyframes and removed; the wall is re-observed
// and kept; what only one keyframe sees stays unconfirmed.
#include <gtest/gtest.h>

#include "core/map/map_points.h"
#include "core/map/static_points.h"

namespace icgm {
namespace {

constexpr int kCols = 80, kRows = 60;

CameraIntrinsics SmallCamera() {
  CameraIntrinsics k;
  k.fx_px = k.fy_px = 60.0;
  k.cx_px = 39.5;
  k.cy_px = 29.5;
  k.width_px = kCols;
  k.height_px = kRows;
  return k;
}

// A keyframe at x = `x_m` (camera axes = map axes: z forward) seeing a wall at z = 4 m; with
// `person`, a 2 m deep block covers the columns [30, 50) of the image.
Keyframe WallKeyframe(double x_m, bool person, double t_s) {
  Keyframe k;
  k.stamp = Time::FromSeconds(t_s);
  k.relative_pose.translation() = Eigen::Vector3d(x_m, 0, 0);
  k.images.intrinsics = SmallCamera();
  k.images.depth_mm = cv::Mat(kRows, kCols, CV_16UC1, cv::Scalar(4000));
  if (person) k.images.depth_mm(cv::Rect(30, 10, 20, 40)).setTo(2000);
  return k;
}

HybridMap Map(const std::vector<Keyframe>& keyframes) {
  HybridMap map;
  Pose3 previous = Pose3::Identity();
  for (Keyframe k : keyframes) {
    const Pose3 global = k.relative_pose;
    k.relative_pose = previous.inverse() * global;  // chained by eq. 6.1
    previous = global;
    int id = -1;
    EXPECT_TRUE(map.AddKeyframe(std::move(k), Mat6::Identity(), &id).ok());
  }
  return map;
}

TEST(StaticPointsTest, PointSeenThroughByOtherKeyframesIsRemoved) {
  const HybridMap map = Map({WallKeyframe(0.0, true, 0.0), WallKeyframe(0.2, false, 2.0),
                             WallKeyframe(-0.2, false, 4.0)});
  const std::vector<MapPoint> points = GatherMapPoints(map, MapCloudOptions());
  ASSERT_EQ(points.size(), 3u * kCols * kRows);
  StaticPointStats stats;
  const std::vector<uint8_t> keep = VerifyStaticPoints(map, points, StaticPointOptions(), &stats);
  size_t person_points = 0, person_kept = 0, wall_points = 0, wall_kept = 0, centre_wall_kept = 0;
  for (size_t i = 0; i < points.size(); ++i) {
    const MapPoint& p = points[i];
    const bool person = std::abs(p.position_m.z() - 2.0f) < 0.01f;
    (person ? person_points : wall_points) += 1;
    (person ? person_kept : wall_kept) += keep[i];
    if (!person && std::abs(p.position_m.x()) < 0.5f && std::abs(p.position_m.y()) < 0.5f) {
      centre_wall_kept += keep[i];
    }
  }
  EXPECT_EQ(person_points, 20u * 40u);
  EXPECT_EQ(person_kept, 0u);  // every person point is seen through
  EXPECT_GE(stats.seen_through, person_points);
  // The wall in the middle of the view is seen by all three keyframes: all kept. At the sides a
  // strip only one keyframe sees stays unconfirmed.
  EXPECT_GT(centre_wall_kept, 0u);
  EXPECT_GT(wall_kept, 0.8 * wall_points);
  EXPECT_LT(wall_kept, wall_points);
  EXPECT_EQ(stats.kept, wall_kept + person_kept);
  EXPECT_EQ(stats.points, points.size());

  StaticPointOptions off;
  off.enabled = false;
  const std::vector<uint8_t> all = VerifyStaticPoints(map, points, off);
  EXPECT_EQ(SelectPoints(points, all).size(), points.size());
}

TEST(StaticPointsTest, PersonStandingStillIsKeptAsStructure) {
  // Seen at the same place by every keyframe: indistinguishable from furniture, kept.
  const HybridMap map = Map({WallKeyframe(0.0, true, 0.0), WallKeyframe(0.0, true, 2.0)});
  const std::vector<MapPoint> points = GatherMapPoints(map, MapCloudOptions());
  StaticPointStats stats;
  VerifyStaticPoints(map, points, StaticPointOptions(), &stats);
  EXPECT_EQ(stats.kept, points.size());
}

TEST(StaticPointsTest, OnlyLooksFarEnoughApartInTimeConfirm) {
  // A walker is where it was a moment ago: a look 0.2 s later confirms nothing.
  const HybridMap map = Map({WallKeyframe(0.0, true, 0.0), WallKeyframe(0.0, true, 0.2)});
  const std::vector<MapPoint> points = GatherMapPoints(map, MapCloudOptions());
  StaticPointStats stats;
  VerifyStaticPoints(map, points, StaticPointOptions(), &stats);
  EXPECT_EQ(stats.kept, 0u);
  EXPECT_EQ(stats.unconfirmed, points.size());
  StaticPointOptions any_time;
  any_time.min_agreement_gap_s = 0.0;
  VerifyStaticPoints(map, points, any_time, &stats);
  EXPECT_EQ(stats.kept, points.size());
}

TEST(StaticPointsTest, FeatureOnlyMapsNeedReobservation) {
  HybridMap map;
  for (int i = 0; i < 2; ++i) {
    Keyframe k;
    k.stamp = Time::FromSeconds(2.0 * i);
    k.keypoints = {cv::KeyPoint(10, 10, 7), cv::KeyPoint(20, 10, 7)};
    // Point 0 is the same map point in both; point 1 moved 0.5 m (a walker).
    k.points_m = {Eigen::Vector3d(0, 0, 2), Eigen::Vector3d(1.0 + 0.5 * i, 0, 2)};
    k.descriptors = cv::Mat(2, 32, CV_8U, cv::Scalar(i));
    int id = -1;
    ASSERT_TRUE(map.AddKeyframe(k, Mat6::Identity(), &id).ok());
  }
  const std::vector<MapPoint> points = GatherMapPoints(map, MapCloudOptions());
  ASSERT_EQ(points.size(), 4u);
  const std::vector<uint8_t> keep = VerifyStaticPoints(map, points, StaticPointOptions());
  EXPECT_EQ(std::vector<uint8_t>(keep.begin(), keep.end()), (std::vector<uint8_t>{1, 0, 1, 0}));
}

}  // namespace
}  // namespace icgm
