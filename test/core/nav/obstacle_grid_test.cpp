#include "core/nav/obstacle_grid.h"

#include <cmath>
#include <limits>
#include <utility>
#include <vector>

#include <gtest/gtest.h>

#include "core/nav/planar_pose.h"
#include "synthetic_depth.h"

namespace icgm {
namespace {

using test::Box;

Time At(double s) { return Time::FromSeconds(100.0 + s); }

// A person-sized box 2.5 m ahead of a robot at the origin facing +x.
const Box kPerson{2.4, 2.7, -0.2, 0.2, 1.7};

// The test camera has a quarter of a Kinect's 640 x 480 pixels: sample every pixel (as every
// 4th of a Kinect image).
ObstacleGridOptions Options() {
  ObstacleGridOptions options;
  options.pixel_step = 1;
  return options;
}

// The face x = x_face of a box falls in the cell on either side of the boundary.
bool AtFace(const ObstacleGrid& grid, double x_face, double y) {
  return grid.Obstacle(x_face - 0.02, y) || grid.Obstacle(x_face + 0.02, y);
}

Status AddView(ObstacleGrid* grid, double t_s, const Pose2D& base, const std::vector<Box>& boxes) {
  const CameraIntrinsics k = test::SmallCamera();
  const Pose3 T_map_base = ToPose3(base);
  const cv::Mat depth = test::RenderDepth(k, T_map_base * test::MountPose(), boxes);
  return grid->AddDepth(At(t_s), depth, k, test::MountPose(), T_map_base);
}

TEST(ObstacleGridTest, PersonIsAnObstacleAndTheFloorIsFree) {
  ObstacleGrid grid(Options());
  ASSERT_TRUE(AddView(&grid, 0.0, Pose2D(), {kPerson}));
  EXPECT_TRUE(AtFace(grid, 2.4, 0.0));   // the person's visible face
  EXPECT_TRUE(AtFace(grid, 2.4, 0.15));
  EXPECT_FALSE(grid.Obstacle(2.0, 0.0));   // floor in front of it
  EXPECT_FALSE(grid.Obstacle(2.38, 0.5));  // floor beside it
  EXPECT_FALSE(grid.Obstacle(-1.0, 0.0));  // behind the robot: never seen
  // Clearance to the face x = 2.4 (cell edges at the 0.05 m grid).
  EXPECT_NEAR(grid.Clearance(1.9, 0.0), 0.5, 0.06);
  EXPECT_TRUE(grid.Occupied(2.0, 0.0));    // within radius + clearance = 0.55 m
  EXPECT_FALSE(grid.Occupied(1.7, 0.0));
  EXPECT_DOUBLE_EQ(grid.Clearance(-3.5, 3.5), grid.max_clearance_m());

  const OccupancyGrid data = grid.Export();
  ASSERT_EQ(data.width, 160);
  ASSERT_EQ(data.data.size(), static_cast<size_t>(data.width * data.height));
  const auto value = [&](double x, double y) {
    const int c = static_cast<int>(std::floor((x - data.origin_m.x()) / data.resolution_m));
    const int r = static_cast<int>(std::floor((y - data.origin_m.y()) / data.resolution_m));
    return data.data[static_cast<size_t>(r) * data.width + c];
  };
  EXPECT_TRUE(value(2.38, 0.0) == 100 || value(2.42, 0.0) == 100);
  EXPECT_EQ(value(2.1, 0.0), 99);   // inflation
  EXPECT_EQ(value(3.5, 0.8), 0);    // floor seen beside
  EXPECT_EQ(value(-2.0, 0.0), -1);  // behind the robot
}

TEST(ObstacleGridTest, FloorAndCeilingAreNotObstacles) {
  ObstacleGridOptions options = Options();
  options.max_height_m = 1.2;
  ObstacleGrid grid(options);
  // A table top at 0.75 m is an obstacle; a board hanging at 1.5-2.0 m is above the band.
  const Box table{2.0, 2.6, -0.5, 0.5, 0.75};
  ASSERT_TRUE(AddView(&grid, 0.0, Pose2D(), {table}));
  EXPECT_TRUE(AtFace(grid, 2.0, 0.0));
  EXPECT_EQ(ObstacleGrid().ObstacleCount(), 0);
  ObstacleGrid floor_only(Options());
  ASSERT_TRUE(AddView(&floor_only, 0.0, Pose2D(), {}));
  EXPECT_EQ(floor_only.ObstacleCount(), 0);
}

TEST(ObstacleGridTest, WalkerThatLeftIsClearedOutOfViewIsRememberedForMemoryS) {
  ObstacleGridOptions options = Options();
  options.memory_s = 2.0;
  ObstacleGrid grid(options);
  ASSERT_TRUE(AddView(&grid, 0.0, Pose2D(), {kPerson}));
  ASSERT_TRUE(AtFace(grid, 2.4, 0.0));
  // The walker moved on: the depth now reaches the floor behind its cell.
  ASSERT_TRUE(AddView(&grid, 0.1, Pose2D(), {}));
  EXPECT_FALSE(AtFace(grid, 2.4, 0.0));

  // Seen again, then the robot turns away: the cell is out of view and kept ...
  ASSERT_TRUE(AddView(&grid, 0.2, Pose2D(), {kPerson}));
  const Pose2D turned{0.0, 0.0, M_PI};
  ASSERT_TRUE(AddView(&grid, 1.0, turned, {kPerson}));
  EXPECT_TRUE(AtFace(grid, 2.4, 0.0));
  ASSERT_TRUE(AddView(&grid, 2.1, turned, {kPerson}));
  EXPECT_TRUE(AtFace(grid, 2.4, 0.0));
  // ... until memory_s after it was last seen.
  ASSERT_TRUE(AddView(&grid, 2.3, turned, {kPerson}));
  EXPECT_FALSE(AtFace(grid, 2.4, 0.0));
}

TEST(ObstacleGridTest, WindowRollsWithTheRobotKeepingMapPositions) {
  ObstacleGrid grid(Options());
  ASSERT_TRUE(AddView(&grid, 0.0, Pose2D(), {kPerson}));
  // The robot moved 1.5 m forward and looks sideways (the person out of view).
  ASSERT_TRUE(AddView(&grid, 0.5, Pose2D{1.5, 0.0, M_PI / 2}, {kPerson}));
  EXPECT_TRUE(AtFace(grid, 2.4, 0.0));
  EXPECT_FALSE(AtFace(grid, 2.4 - 1.5, 0.0));
  // Far away: the cell left the window.
  grid.AddPoints(At(0.6), Eigen::Vector2d(10.0, 0.0), {});
  EXPECT_FALSE(AtFace(grid, 2.4, 0.0));
  EXPECT_EQ(grid.ObstacleCount(), 0);
}

TEST(ObstacleGridTest, WithDiscsMarksTheDiscsInACopyOnly) {
  ObstacleGrid grid(Options());
  grid.AddPoints(At(0.0), Eigen::Vector2d::Zero(), {Eigen::Vector2d(-2.0, 0.0)});
  const double before = grid.Clearance(2.0, 0.0);
  ASSERT_GT(before, 1.0);
  // The second disc lies off the window.
  const ObstacleGrid swept =
      grid.WithDiscs({{Eigen::Vector2d(2.0, 0.0), 0.3}, {Eigen::Vector2d(40.0, 0.0), 0.3}});
  EXPECT_TRUE(swept.Obstacle(2.0, 0.0));
  EXPECT_TRUE(swept.Obstacle(2.22, 0.0));
  EXPECT_FALSE(swept.Obstacle(2.4, 0.0));
  EXPECT_TRUE(swept.Obstacle(-2.0, 0.0));  // the grid's own obstacle stays
  // Clearance from the disc's edge (cells whose centres are inside it: within a cell).
  EXPECT_NEAR(swept.Clearance(3.0, 0.0), 0.7, 0.06);
  EXPECT_TRUE(swept.Occupied(2.7, 0.0));
  int inside = 0;  // cells (5 cm) whose centres lie within the disc
  for (int i = -8; i < 8; ++i) {
    for (int j = -8; j < 8; ++j) inside += std::hypot((i + 0.5) * 0.05, (j + 0.5) * 0.05) <= 0.3;
  }
  EXPECT_EQ(swept.ObstacleCount(), grid.ObstacleCount() + inside);
  // The original is unchanged, its distances included (cv::Mat copies share pixels).
  EXPECT_FALSE(grid.Obstacle(2.0, 0.0));
  EXPECT_DOUBLE_EQ(grid.Clearance(2.0, 0.0), before);
}

TEST(ObstacleGridTest, RejectsBadDepth) {
  ObstacleGrid grid;
  const Status s = grid.AddDepth(At(0), cv::Mat(), test::SmallCamera(), test::MountPose(),
                                 Pose3::Identity());
  EXPECT_FALSE(s.ok());
  EXPECT_NE(s.reason().find("CV_32FC1"), std::string::npos);
  EXPECT_FALSE(grid.AddDepth(At(0), cv::Mat(10, 10, CV_16U), test::SmallCamera(),
                             test::MountPose(), Pose3::Identity())
                   .ok());
}


// A scan of `beams` beams all round from angle 0 (forward), every range `far` except those
// listed (beam index -> range).
PlanarScan RoundScan(double t_s, int beams, float far, const std::vector<std::pair<int, float>>& hits) {
  PlanarScan scan;
  scan.stamp = At(t_s);
  scan.angle_min_rad = 0.0;
  scan.angle_increment_rad = 2.0 * M_PI / beams;
  scan.range_min_m = 0.1;
  scan.range_max_m = 6.0;
  scan.ranges_m.assign(static_cast<size_t>(beams), far);
  for (const auto& [i, r] : hits) scan.ranges_m[static_cast<size_t>(i)] = r;
  return scan;
}

Pose3 ScannerMount(double forward_m, double height_m) {
  Pose3 T = Pose3::Identity();
  T.translation() = Eigen::Vector3d(forward_m, 0.0, height_m);
  return T;
}

TEST(ObstacleGridScanTest, ReturnsArePointsInBaseLink) {
  // Beam 0 forward 2 m, beam 90 (of 360) to the left 1 m, beam 180 behind 1.5 m; beam 270 out
  // of range, beam 1 below range_min: no returns.
  const PlanarScan scan = RoundScan(0.0, 360, std::numeric_limits<float>::infinity(),
                                    {{0, 2.0f}, {90, 1.0f}, {180, 1.5f}, {270, 7.0f}, {1, 0.05f}});
  const std::vector<Eigen::Vector3d> p = ScanPointsInBase(scan, ScannerMount(0.1, 1.0));
  ASSERT_EQ(p.size(), 3u);
  EXPECT_TRUE(p[0].isApprox(Eigen::Vector3d(2.1, 0.0, 1.0), 1e-6));
  EXPECT_NEAR(p[1].x(), 0.1, 1e-6);
  EXPECT_NEAR(p[1].y(), 1.0, 1e-6);
  EXPECT_NEAR(p[2].x(), -1.4, 1e-6);
  EXPECT_NEAR(p[2].y(), 0.0, 1e-6);
}

TEST(ObstacleGridScanTest, ScanMarksBesideAndBehindAndClearsWhatMovedOn) {
  ObstacleGrid grid(Options());
  // Robot at (1.02, 2.02) facing +y (points off the cells' edges): beam 0 (forward) hits at
  // (1.02, 4.12), beam 180 (behind) at (1.02, 0.62), beam 90 (left: -x) at (-0.48, 2.12).
  const Pose3 T_map_base = ToPose3(Pose2D{1.02, 2.02, M_PI / 2});
  const Pose3 mount = ScannerMount(0.1, 1.0);
  grid.AddScan(RoundScan(0.0, 360, std::numeric_limits<float>::infinity(),
                         {{0, 2.0f}, {180, 1.5f}, {90, 1.5f}}),
               mount, T_map_base, false);
  EXPECT_TRUE(grid.Obstacle(1.02, 4.12));
  EXPECT_TRUE(grid.Obstacle(1.02, 0.62));
  EXPECT_TRUE(grid.Obstacle(-0.48, 2.12));
  EXPECT_EQ(grid.fresh_obstacles_m().size(), 3u);
  EXPECT_FALSE(grid.Obstacle(1.02, 3.52));  // along the beam, before the return
  EXPECT_NEAR(grid.Clearance(1.02, 3.62), 0.45, 0.06);
  // The walker behind moved on: beam 180 returns nothing now; the others still return.
  grid.AddScan(RoundScan(0.1, 360, std::numeric_limits<float>::infinity(), {{0, 2.0f}, {90, 1.5f}}),
               mount, T_map_base, false);
  EXPECT_FALSE(grid.Obstacle(1.02, 0.62));
  EXPECT_TRUE(grid.Obstacle(1.02, 4.12));
  EXPECT_EQ(grid.fresh_obstacles_m().size(), 2u);
  // A scan plane above the height band marks nothing.
  ObstacleGrid high(Options());
  high.AddScan(RoundScan(0.0, 360, 3.0f, {}), ScannerMount(0.0, 2.0), T_map_base, false);
  EXPECT_EQ(high.ObstacleCount(), 0);
}

TEST(ObstacleGridScanTest, ScanJoinsTheDepthOfTheSameFrameAndLeavesItsObstacles) {
  ObstacleGrid grid(Options());
  // The camera sees a table 2.0-2.6 m ahead (0.75 m high); a scan at 1.0 m passes over it and
  // sees a walker 1 m behind the robot.
  const Box table{2.0, 2.6, -0.5, 0.5, 0.75};
  ASSERT_TRUE(AddView(&grid, 0.0, Pose2D(), {table}));
  const size_t depth_cells = grid.fresh_obstacles_m().size();
  ASSERT_GT(depth_cells, 0u);
  grid.AddScan(RoundScan(0.0, 360, std::numeric_limits<float>::infinity(), {{180, 1.0f}}),
               ScannerMount(0.0, 1.0), Pose3::Identity(), true);
  EXPECT_TRUE(AtFace(grid, 2.0, 0.0));  // not cleared by the beam over it
  EXPECT_TRUE(grid.Obstacle(-1.0, 0.0));
  EXPECT_EQ(grid.fresh_obstacles_m().size(), depth_cells + 1);
  // The next frame's scan alone (the camera looking elsewhere) still leaves the table.
  grid.AddScan(RoundScan(0.1, 360, std::numeric_limits<float>::infinity(), {}),
               ScannerMount(0.0, 1.0), Pose3::Identity(), false);
  EXPECT_TRUE(AtFace(grid, 2.0, 0.0));
  EXPECT_FALSE(grid.Obstacle(-1.0, 0.0));
  EXPECT_TRUE(grid.fresh_obstacles_m().empty());
}

TEST(ObstacleGridTest, ForgetClearsChosenCellsAndWithoutLeavesTheGridUnchanged) {
  ObstacleGrid grid(Options());
  // Two obstacles 1 m apart: (2.02, 0.02) and (2.02, 1.02).
  grid.AddPoints(At(0.0), Eigen::Vector2d::Zero(), {{2.02, 0.02}, {2.02, 1.02}});
  const std::vector<Eigen::Vector2d> near = grid.ObstacleCells(Disc{{2.0, 0.0}, 0.3});
  ASSERT_EQ(near.size(), 1u);
  EXPECT_NEAR(near[0].x(), 2.025, 1e-9);
  EXPECT_NEAR(near[0].y(), 0.025, 1e-9);
  EXPECT_EQ(grid.ObstacleCells(Disc{{2.0, 0.5}, 0.6}).size(), 2u);

  const ObstacleGrid without = grid.Without(near);
  EXPECT_FALSE(without.Obstacle(2.02, 0.02));
  EXPECT_TRUE(without.Obstacle(2.02, 1.02));
  EXPECT_GT(without.Clearance(2.02, 0.3), 0.6);  // now measured to the other obstacle
  EXPECT_TRUE(grid.Obstacle(2.02, 0.02));        // the original keeps both
  EXPECT_LT(grid.Clearance(2.02, 0.3), 0.3);

  grid.Forget({{2.02, 1.02}, {9.0, 9.0}});  // outside the window: ignored
  EXPECT_FALSE(grid.Obstacle(2.02, 1.02));
  EXPECT_TRUE(grid.Obstacle(2.02, 0.02));
  EXPECT_EQ(grid.ObstacleCount(), 1);
  EXPECT_GT(grid.Clearance(2.02, 1.02), 0.9);
}

}  // namespace
}  // namespace icgm
