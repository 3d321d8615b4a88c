// Export round trip: a known cloud through the voxel filter, written as PCD and PLY, read back
// with PCL: the same count, bounds and colours.
#include <unistd.h>

#include <filesystem>
#include <random>
#include <set>
#include <tuple>

#include <gtest/gtest.h>

#include <pcl/common/common.h>

#include "core/map_export/cloud_export.h"

namespace icgm {
namespace {

std::vector<MapPoint> RandomPoints(size_t n) {
  std::mt19937 rng(3);
  std::uniform_real_distribution<float> x(-2.0f, 3.0f), y(-1.0f, 1.0f), z(0.0f, 2.0f);
  std::vector<MapPoint> points(n);
  for (MapPoint& p : points) {
    p.position_m = Eigen::Vector3f(x(rng), y(rng), z(rng));
    p.bgr = cv::Vec3b(10, 200, 90);
  }
  return points;
}

TEST(CloudExportTest, VoxelFilterKeepsOnePointPerOccupiedVoxel) {
  const std::vector<MapPoint> points = RandomPoints(20000);
  const double leaf = 0.1;
  std::set<std::tuple<int, int, int>> voxels;
  for (const MapPoint& p : points) {
    const Eigen::Vector3i v = VoxelIndex(p.position_m, leaf);
    voxels.insert({v.x(), v.y(), v.z()});
  }
  const ColouredCloud filtered = VoxelFilter(ToPclCloud(points), leaf);
  EXPECT_EQ(filtered.size(), voxels.size());
  for (const auto& p : filtered) {
    // A centroid stays in its voxel; the colours were all the same.
    const Eigen::Vector3i v = VoxelIndex(Eigen::Vector3f(p.x, p.y, p.z), leaf);
    EXPECT_TRUE(voxels.count({v.x(), v.y(), v.z()}));
    EXPECT_EQ(p.g, 200);
  }
  EXPECT_EQ(VoxelFilter(ToPclCloud(points), 0.0).size(), points.size());
}

TEST(CloudExportTest, PcdAndPlyRoundTrip) {
  const ColouredCloud cloud = VoxelFilter(ToPclCloud(RandomPoints(5000)), 0.05);
  Eigen::Vector4f lo, hi;
  pcl::getMinMax3D(cloud, lo, hi);
  const auto dir = std::filesystem::temp_directory_path() /
                   ("icgm_cloud_" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir);
  for (const char* name : {"cloud.pcd", "cloud.ply"}) {
    const std::string path = (dir / name).string();
    ASSERT_TRUE(SaveCloud(cloud, path).ok()) << name;
    ColouredCloud back;
    ASSERT_TRUE(LoadCloud(path, &back).ok()) << name;
    ASSERT_EQ(back.size(), cloud.size()) << name;
    Eigen::Vector4f blo, bhi;
    pcl::getMinMax3D(back, blo, bhi);
    EXPECT_LT((blo - lo).head<3>().norm(), 1e-6) << name;
    EXPECT_LT((bhi - hi).head<3>().norm(), 1e-6) << name;
    EXPECT_EQ(back[17].r, cloud[17].r) << name;
    EXPECT_EQ(back[17].b, cloud[17].b) << name;
  }
  EXPECT_FALSE(SaveCloud(cloud, (dir / "cloud.xyz").string()).ok());
  EXPECT_FALSE(SaveCloud(ColouredCloud(), (dir / "empty.pcd").string()).ok());
  std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace icgm
