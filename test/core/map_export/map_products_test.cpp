// The map products on a constructed map: three keyframes 1 m above the floor, side by side,
// look along the map's x axis at a wall 4 m away; the first also sees a person 2 m ahead, who
// has left when the others look. The person is neither in the cloud nor in the grid, the wall
// is in both, and the space between is free.
#include "core/map_export/map_products.h"

#include <gtest/gtest.h>

#include "core/map_export/cloud_export.h"

namespace icgm {
namespace {

constexpr int kCols = 80, kRows = 60;

Keyframe WallKeyframe(double y_m, bool person, double t_s) {
  Keyframe k;
  k.stamp = Time::FromSeconds(t_s);
  // Camera axes (x right, y down, z forward) in the map (z up): looking along +x.
  Eigen::Matrix3d r;
  r << 0, 0, 1, -1, 0, 0, 0, -1, 0;
  k.relative_pose.linear() = r;
  k.relative_pose.translation() = Eigen::Vector3d(0.0, y_m, 1.0);
  CameraIntrinsics& c = k.images.intrinsics;
  c.fx_px = c.fy_px = 60.0;
  c.cx_px = 39.5;
  c.cy_px = 29.5;
  c.width_px = kCols;
  c.height_px = kRows;
  k.images.depth_mm = cv::Mat(kRows, kCols, CV_16UC1, cv::Scalar(4000));
  k.images.bgr = cv::Mat(kRows, kCols, CV_8UC3, cv::Scalar(10, 20, 30));
  if (person) k.images.depth_mm(cv::Rect(30, 10, 20, 40)).setTo(2000);
  return k;
}

HybridMap Map() {
  HybridMap map;
  Pose3 previous = Pose3::Identity();
  const std::vector<Keyframe> keyframes{WallKeyframe(0.0, true, 0.0), WallKeyframe(0.2, false, 2.0),
                                        WallKeyframe(-0.2, false, 4.0)};
  for (Keyframe k : keyframes) {
    const Pose3 global = k.relative_pose;
    k.relative_pose = previous.inverse() * global;
    previous = global;
    int id = -1;
    EXPECT_TRUE(map.AddKeyframe(std::move(k), Mat6::Identity(), &id).ok());
  }
  return map;
}

size_t PointsNear(const std::vector<MapPoint>& cloud, float x_m) {
  size_t n = 0;
  for (const MapPoint& p : cloud) n += std::abs(p.position_m.x() - x_m) < 0.05f ? 1 : 0;
  return n;
}

int8_t CellAt(const OccupancyGrid& grid, double x, double y) {
  int cx = 0, cy = 0;
  if (!grid.CellOf(Eigen::Vector2d(x, y), &cx, &cy)) return OccupancyGrid::kUnknown;
  return grid.at(cx, cy);
}

TEST(MapProductsTest, PersonRemovedFromCloudAndGridWallKept) {
  const HybridMap map = Map();
  MapProducts products;
  ASSERT_TRUE(BuildMapProducts(map, MapExportOptions(), &products).ok());
  EXPECT_EQ(products.stats.points, 3u * kCols * kRows);
  EXPECT_GT(products.stats.seen_through, 0u);
  // One point per 2 cm voxel: far fewer than the static points.
  ASSERT_FALSE(products.cloud.empty());
  EXPECT_LT(products.cloud.size(), products.stats.kept / 2);
  EXPECT_EQ(PointsNear(products.cloud, 2.0f), 0u);
  EXPECT_GT(PointsNear(products.cloud, 4.0f), 0.9 * products.cloud.size());
  EXPECT_EQ(products.cloud.front().bgr, cv::Vec3b(10, 20, 30));
  // The wall is occupied, where the person stood is free, behind the wall is unknown.
  EXPECT_EQ(CellAt(products.grid, 4.01, 0.0), OccupancyGrid::kOccupied);
  EXPECT_EQ(CellAt(products.grid, 4.01, 1.0), OccupancyGrid::kOccupied);
  EXPECT_EQ(CellAt(products.grid, 2.01, 0.0), OccupancyGrid::kFree);
  EXPECT_EQ(CellAt(products.grid, 1.0, 0.0), OccupancyGrid::kFree);
  EXPECT_EQ(CellAt(products.grid, 4.3, 0.0), OccupancyGrid::kUnknown);

  // Without the static check the person is in the cloud: the check removed it.
  MapExportOptions all;
  all.static_points.enabled = false;
  MapProducts unchecked;
  ASSERT_TRUE(BuildMapProducts(map, all, &unchecked).ok());
  EXPECT_GT(PointsNear(unchecked.cloud, 2.0f), 0u);
}

// One sequence for the tool and the map builder: the products equal the steps run one by one
// (gather -> static check -> grid -> voxel filter), the cloud field by field as written to a
// file; the progress reaches every keyframe; the points are kept only when asked for.
TEST(MapProductsTest, EqualToTheStepsOneByOneWithProgress) {
  const HybridMap map = Map();
  const MapExportOptions options;
  const std::vector<MapPoint> points = GatherMapPoints(map, options.cloud);
  StaticPointStats stats;
  const std::vector<MapPoint> kept =
      SelectPoints(points, VerifyStaticPoints(map, points, options.static_points, &stats));
  const OccupancyGrid grid = BuildOccupancyGrid(map, kept, options.grid);
  const ColouredCloud voxels = VoxelFilter(ToPclCloud(kept), options.cloud.voxel_m);

  size_t calls = 0, last_done = 0, last_total = 0;
  MapProducts products;
  ASSERT_TRUE(BuildMapProducts(map, options, &products,
                               [&](size_t done, size_t total) {
                                 ++calls;
                                 EXPECT_GE(done, last_done);
                                 last_done = done;
                                 last_total = total;
                               },
                               /*keep_points=*/true)
                  .ok());
  EXPECT_GT(calls, 0u);
  EXPECT_EQ(last_total, static_cast<size_t>(map.size()));
  EXPECT_EQ(last_done, last_total);
  EXPECT_EQ(products.stats.points, stats.points);
  EXPECT_EQ(products.stats.kept, stats.kept);
  EXPECT_EQ(products.stats.seen_through, stats.seen_through);
  EXPECT_EQ(products.stats.unconfirmed, stats.unconfirmed);
  ASSERT_EQ(products.points.size(), points.size());
  ASSERT_EQ(products.static_points.size(), kept.size());
  for (size_t i = 0; i < kept.size(); ++i) {
    EXPECT_EQ(products.static_points[i].position_m, kept[i].position_m);
  }
  EXPECT_EQ(products.grid.width, grid.width);
  EXPECT_EQ(products.grid.height, grid.height);
  EXPECT_EQ(products.grid.resolution_m, grid.resolution_m);
  EXPECT_EQ(products.grid.origin_m, grid.origin_m);
  EXPECT_EQ(products.grid.data, grid.data);
  const ColouredCloud cloud = ToPclCloud(products.cloud);
  ASSERT_EQ(cloud.size(), voxels.size());
  for (size_t i = 0; i < cloud.size(); ++i) {
    EXPECT_EQ(cloud[i].x, voxels[i].x);
    EXPECT_EQ(cloud[i].y, voxels[i].y);
    EXPECT_EQ(cloud[i].z, voxels[i].z);
    EXPECT_EQ(cloud[i].rgba, voxels[i].rgba) << "point " << i;
  }

  MapProducts without_points;
  ASSERT_TRUE(BuildMapProducts(map, options, &without_points).ok());
  EXPECT_TRUE(without_points.points.empty());
  EXPECT_TRUE(without_points.static_points.empty());
  EXPECT_EQ(without_points.cloud.size(), products.cloud.size());
}

TEST(MapProductsTest, EmptyMapFails) {
  MapProducts products;
  const Status s = BuildMapProducts(HybridMap(), MapExportOptions(), &products);
  EXPECT_FALSE(s.ok());
  EXPECT_NE(s.reason().find("no keyframes"), std::string::npos);
}

}  // namespace
}  // namespace icgm
