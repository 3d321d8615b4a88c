// Occupancy grid from a hand-built cloud: a camera 0.5 m above the floor looks along +x at a wall
// 3 m away and at the floor before it. The wall's cells are occupied, the cells between free,
// the cells behind the wall and behind the camera unknown; the map_server files hold the same.
#include <filesystem>
#include <fstream>
#include <sstream>

#include <unistd.h>

#include <gtest/gtest.h>
#include <opencv2/imgcodecs.hpp>

#include "core/map/occupancy_grid.h"
#include "core/map/occupancy_grid_io.h"

namespace icgm {
namespace {

MapPoint Point(double x, double y, double z) {
  MapPoint p;
  p.position_m = Eigen::Vector3f(x, y, z);
  p.keyframe_id = 0;
  return p;
}

std::vector<MapPoint> WallAndFloor() {
  std::vector<MapPoint> points;
  for (double y = -1.0; y <= 1.0; y += 0.02) {
    for (double z = 0.0; z <= 1.5; z += 0.05) points.push_back(Point(3.025, y, z));  // wall
    for (double x = 0.5; x < 3.0; x += 0.05) points.push_back(Point(x, y, 0.0));   // floor
  }
  return points;
}

int8_t CellAt(const OccupancyGrid& grid, double x, double y) {
  int cx = 0, cy = 0;
  EXPECT_TRUE(grid.CellOf({x, y}, &cx, &cy)) << x << " " << y;
  return grid.at(cx, cy);
}

TEST(OccupancyGridTest, WallsOccupiedBetweenFreeUnseenUnknown) {
  const std::vector<Eigen::Vector3d> cameras = {{0.0, 0.0, 0.5}};
  OccupancyGridOptions options;
  const OccupancyGrid grid = BuildOccupancyGrid(cameras, WallAndFloor(), options);
  ASSERT_GT(grid.width, 0);
  EXPECT_EQ(CellAt(grid, 3.025, 0.0), OccupancyGrid::kOccupied);
  EXPECT_EQ(CellAt(grid, 3.025, 0.9), OccupancyGrid::kOccupied);
  EXPECT_EQ(CellAt(grid, 1.5, 0.0), OccupancyGrid::kFree);
  EXPECT_EQ(CellAt(grid, 2.5, -0.5), OccupancyGrid::kFree);
  EXPECT_EQ(CellAt(grid, 0.3, 0.0), OccupancyGrid::kFree);
  EXPECT_EQ(CellAt(grid, 3.3, 0.0), OccupancyGrid::kUnknown);   // behind the wall
  EXPECT_EQ(CellAt(grid, -0.4, 0.0), OccupancyGrid::kUnknown);  // behind the camera
  EXPECT_EQ(CellAt(grid, 1.5, 1.4), OccupancyGrid::kUnknown);   // outside the view
  // The wall is one cell thick along x and spans y in [-1, 1].
  size_t occupied = grid.Count(OccupancyGrid::kOccupied);
  EXPECT_GE(occupied, 40u);
  EXPECT_LE(occupied, 45u);
}

TEST(OccupancyGridTest, HeightBandAndRangeLimitHits) {
  const std::vector<Eigen::Vector3d> cameras = {{0.0, 0.0, 0.5}};
  OccupancyGridOptions options;
  std::vector<MapPoint> points;
  for (int i = 0; i < 5; ++i) {
    points.push_back(Point(2.0, 0.0, 2.5));  // above the band: not an obstacle
    points.push_back(Point(0.0, 2.0, 0.05)); // below it
    points.push_back(Point(-7.0, 0.0, 1.0)); // beyond max_range_m
    points.push_back(Point(2.525, 1.0, 1.0)); // one obstacle, which also bounds the grid
  }
  const OccupancyGrid grid = BuildOccupancyGrid(cameras, points, options);
  EXPECT_EQ(grid.Count(OccupancyGrid::kOccupied), 1u);
  EXPECT_EQ(CellAt(grid, 2.525, 1.0), OccupancyGrid::kOccupied);
  EXPECT_EQ(CellAt(grid, 1.0, 0.0), OccupancyGrid::kFree);  // the ray rose through the band
  options.max_height_m = 3.0;
  EXPECT_EQ(CellAt(BuildOccupancyGrid(cameras, points, options), 2.0, 0.0),
            OccupancyGrid::kOccupied);
}

TEST(OccupancyGridTest, MapServerFiles) {
  const std::vector<Eigen::Vector3d> cameras = {{0.0, 0.0, 0.5}};
  const OccupancyGrid grid = BuildOccupancyGrid(cameras, WallAndFloor(), OccupancyGridOptions());
  const auto dir = std::filesystem::temp_directory_path() /
                   ("icgm_grid_" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir);
  std::string pgm, yaml;
  ASSERT_TRUE(WriteMapServerGrid(grid, (dir / "grid.pgm").string(), &pgm, &yaml).ok());
  const cv::Mat image = cv::imread(pgm, cv::IMREAD_UNCHANGED);
  ASSERT_EQ(image.cols, grid.width);
  ASSERT_EQ(image.rows, grid.height);
  size_t black = 0, white = 0, grey = 0;
  for (int r = 0; r < image.rows; ++r) {
    for (int c = 0; c < image.cols; ++c) {
      const uint8_t v = image.at<uint8_t>(r, c);
      const int8_t cell = grid.at(c, grid.height - 1 - r);
      EXPECT_EQ(v, cell == OccupancyGrid::kOccupied ? 0 : cell == OccupancyGrid::kFree ? 254 : 205);
      black += v == 0;
      white += v == 254;
      grey += v == 205;
    }
  }
  EXPECT_EQ(black, grid.Count(OccupancyGrid::kOccupied));
  EXPECT_EQ(white, grid.Count(OccupancyGrid::kFree));
  EXPECT_EQ(grey, grid.Count(OccupancyGrid::kUnknown));
  std::ifstream in(yaml);
  std::stringstream text;
  text << in.rdbuf();
  EXPECT_NE(text.str().find("image: grid.pgm"), std::string::npos) << text.str();
  EXPECT_NE(text.str().find("resolution: 0.05"), std::string::npos) << text.str();
  std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace icgm
