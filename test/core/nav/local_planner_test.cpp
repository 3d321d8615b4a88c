#include "core/nav/local_planner.h"

#include <gtest/gtest.h>

namespace icgm {
namespace {

Time At(double s) { return Time::FromSeconds(50.0 + s); }

// A wall across x = 1.5 from y = -4 to 4 with a gap for y in [gap_lo, gap_hi].
std::vector<Eigen::Vector2d> WallWithGap(double gap_lo, double gap_hi) {
  std::vector<Eigen::Vector2d> points;
  for (double y = -4.0; y <= 4.0; y += 0.02) {
    if (y >= gap_lo && y <= gap_hi) continue;
    points.emplace_back(1.5, y);
  }
  return points;
}

double MinClearance(const LocalPath& path, const ObstacleGrid& grid) {
  double c = 1e9;
  for (const auto& p : path.points_m) c = std::min(c, grid.Clearance(p.x(), p.y()));
  return c;
}

TEST(LocalPlannerTest, StraightPathInFreeSpace) {
  ObstacleGrid grid;
  grid.AddPoints(At(0), Eigen::Vector2d::Zero(), {});
  LocalPlanner planner;
  LocalPath path;
  ASSERT_TRUE(planner.Plan(Pose2D{0, 0, 0}, Pose2D{3, 0, 0}, grid, &path));
  EXPECT_NEAR(path.length_m, 3.0, 0.05);  // simplified to (almost) the straight line
  EXPECT_LT((path.points_m.front() - Eigen::Vector2d(0, 0)).norm(), 1e-9);
  EXPECT_LT((path.points_m.back() - Eigen::Vector2d(3, 0)).norm(), 1e-9);
  for (size_t i = 1; i < path.points_m.size(); ++i) {
    EXPECT_LE((path.points_m[i] - path.points_m[i - 1]).norm(), 0.05 + 1e-9);
  }
}

TEST(LocalPlannerTest, FindsTheGapKeepingClearance) {
  ObstacleGrid grid;
  // Gap of 1.6 m: with 0.55 m inflation on each side the centre may pass within y in [1.55, 2.05].
  grid.AddPoints(At(0), Eigen::Vector2d(1.5, 0.5), WallWithGap(1.0, 2.6));
  LocalPlannerOptions options;
  options.max_state_checks = 200000;  // generous: the test checks the path, not the cost
  LocalPlanner planner(options);
  LocalPath path;
  ASSERT_TRUE(planner.Plan(Pose2D{0, 0, 0}, Pose2D{3, 0, 0}, grid, &path));
  EXPECT_GE(MinClearance(path, grid), grid.inflation_m() - 1e-6);
  bool through_gap = false;
  for (const auto& p : path.points_m) {
    if (std::abs(p.x() - 1.5) < 0.05) through_gap |= p.y() > 1.45 && p.y() < 2.15;
  }
  EXPECT_TRUE(through_gap);
  EXPECT_GT(path.length_m, 2.0 * std::hypot(1.5, 1.55) - 0.05);  // at least via the gap
  EXPECT_TRUE(planner.SegmentFree(Eigen::Vector2d(0, 0), Eigen::Vector2d(0.5, 0), grid));
  EXPECT_FALSE(planner.SegmentFree(Eigen::Vector2d(0, 0), Eigen::Vector2d(3, 0), grid));
}

TEST(LocalPlannerTest, DetourOnASweptGridKeepsOutOfAWalkersPath) {
  // A table (radius 0.3 m) on the straight line to the goal; a walker will pass along y = 1 on
  // its left, where a detour would go if the grid alone counted.
  std::vector<Eigen::Vector2d> table;
  for (double a = 0.0; a < 2.0 * M_PI; a += 0.05) {
    table.emplace_back(2.0 + 0.3 * std::cos(a), 0.3 * std::sin(a));
  }
  ObstacleGrid grid;
  grid.AddPoints(At(0), Eigen::Vector2d(2.0, 0.0), table);
  std::vector<Disc> walker;
  for (double x = 1.0; x <= 3.0 + 1e-9; x += 0.25) {
    walker.push_back({Eigen::Vector2d(x, 1.0), 0.25});
  }
  const ObstacleGrid swept = grid.WithDiscs(walker);
  LocalPlanner planner;
  // Passing left of the table is free on the grid alone, not on the swept grid.
  const std::vector<Eigen::Vector2d> left{{0, 0}, {1.2, 0.95}, {2.8, 0.95}, {4, 0}};
  bool left_free = true, left_free_swept = true;
  for (size_t i = 1; i < left.size(); ++i) {
    left_free = left_free && planner.SegmentFree(left[i - 1], left[i], grid);
    left_free_swept = left_free_swept && planner.SegmentFree(left[i - 1], left[i], swept);
  }
  EXPECT_TRUE(left_free);
  EXPECT_FALSE(left_free_swept);

  LocalPath path;
  ASSERT_TRUE(planner.Plan(Pose2D{0, 0, 0}, Pose2D{4, 0, 0}, swept, &path));
  EXPECT_GE(MinClearance(path, swept), swept.inflation_m() - 1e-6);
  for (const auto& p : path.points_m) {
    if (std::abs(p.x() - 2.0) < 0.3) {
      EXPECT_LT(p.y(), -0.8);  // right of the table
    }
    for (const Disc& d : walker) {
      EXPECT_GE((p - d.centre_m).norm() - d.radius_m, grid.inflation_m() - 0.05);
    }
  }
}

TEST(LocalPlannerTest, ClosedWallIsBlockedWithAReason) {
  ObstacleGrid grid;
  grid.AddPoints(At(0), Eigen::Vector2d(1.5, 0), WallWithGap(10.0, 10.0));
  LocalPlannerOptions options;
  options.window_m = 5.0;  // the wall spans the whole window
  LocalPlanner planner(options);
  LocalPath path;
  Status s = planner.Plan(Pose2D{0, 0, 0}, Pose2D{3, 0, 0}, grid, &path);
  ASSERT_FALSE(s.ok());
  EXPECT_NE(s.reason().find("blocked"), std::string::npos) << s.reason();
  s = planner.Plan(Pose2D{0, 0, 0}, Pose2D{1.7, 0, 0}, grid, &path);
  ASSERT_FALSE(s.ok());
  EXPECT_NE(s.reason().find("inside"), std::string::npos) << s.reason();
}

TEST(LocalPlannerTest, EscapesFromInsideTheInflation) {
  ObstacleGrid grid;
  // A walker came within 0.4 m of the robot (inside 0.55 m inflation, outside the 0.25 m body).
  std::vector<Eigen::Vector2d> walker;
  for (double a = 0; a < 2 * M_PI; a += 0.1) walker.emplace_back(0.6 + 0.2 * std::cos(a), 0.2 * std::sin(a));
  grid.AddPoints(At(0), Eigen::Vector2d::Zero(), walker);
  ASSERT_TRUE(grid.Occupied(0.0, 0.0));
  LocalPlanner planner;
  LocalPath path;
  ASSERT_TRUE(planner.Plan(Pose2D{0, 0, 0}, Pose2D{3, 0, 0}, grid, &path));
  for (const auto& p : path.points_m) {
    EXPECT_GE(grid.Clearance(p.x(), p.y()), grid.options().robot_radius_m);
  }
}

TEST(LocalPlannerTest, SegmentFreeKeepsTheAskedClearanceBeyondTheEscape) {
  ObstacleGrid grid;
  // A row of points along y = 0.45 beside a segment on the x axis from 0 to 3: the centre stays
  // 0.45 m from them minus half a cell at most.
  std::vector<Eigen::Vector2d> row;
  for (double x = 1.0; x <= 2.0; x += 0.02) row.emplace_back(x, 0.45);
  grid.AddPoints(At(0), Eigen::Vector2d::Zero(), row);
  const double gap = grid.Clearance(1.5, 0.0);
  ASSERT_GT(gap, 0.35);
  ASSERT_LT(gap, 0.45);
  LocalPlanner planner;
  const Eigen::Vector2d a(0, 0), b(3, 0);
  // Pieces 5 cm long checked from their own start: the bare footprint (0.25 m) suffices.
  for (double x = 0.0; x < 3.0; x += 0.05) {
    EXPECT_TRUE(planner.SegmentFree(Eigen::Vector2d(x, 0), Eigen::Vector2d(x + 0.05, 0), grid));
  }
  EXPECT_FALSE(planner.SegmentFree(a, b, grid));  // one piece: beyond 0.5 m of a, inflated
  // The escape measured from the robot at a: beyond 0.5 m the grid's inflation (0.55 m).
  EXPECT_FALSE(planner.SegmentFree(a, b, grid, a));
  // A narrower clearance: 0.25 + 0.1 = 0.35 m passes, 0.25 + 0.2 = 0.45 m does not.
  EXPECT_TRUE(planner.SegmentFree(a, b, grid, a, 0.1));
  EXPECT_FALSE(planner.SegmentFree(a, b, grid, a, 0.2));
  // Within start_escape_m of the robot the bare footprint suffices whatever the clearance.
  EXPECT_TRUE(planner.SegmentFree(Eigen::Vector2d(1.3, 0), Eigen::Vector2d(1.7, 0), grid,
                                  Eigen::Vector2d(1.5, 0), 0.2));
}

TEST(LocalPlannerTest, PlansThroughANarrowGapWithASmallerClearanceWhenAsked) {
  ObstacleGrid grid;
  // A gap 0.8 m wide in the wall (its points' cells 5 cm): the footprint (0.5 m) fits, the
  // inflation (0.55 m each side) does not, and the wall reaches beyond the planner's window.
  grid.AddPoints(At(0), Eigen::Vector2d(1.5, 0.0), WallWithGap(-0.42, 0.42));
  LocalPlanner planner;
  LocalPath path;
  EXPECT_FALSE(planner.Plan(Pose2D{0, 0, 0}, Pose2D{3, 0, 0}, grid, &path).ok());
  const Status narrow = planner.Plan(Pose2D{0, 0, 0}, Pose2D{3, 0, 0}, grid, &path, nullptr, 0.1);
  ASSERT_TRUE(narrow.ok()) << narrow.reason();
  double least = 1e9;
  for (const auto& p : path.points_m) least = std::min(least, grid.Clearance(p.x(), p.y()));
  EXPECT_GE(least, grid.options().robot_radius_m + 0.1 - 1e-6);
  EXPECT_LT(least, grid.inflation_m());
}

TEST(LocalPlannerTest, SameInputGivesTheSamePlanWhateverRanBefore) {
  ObstacleGrid grid;
  grid.AddPoints(At(0), Eigen::Vector2d(1.5, 0.5), WallWithGap(1.0, 2.6));
  LocalPlannerOptions options;
  options.max_state_checks = 200000;
  const LocalPlanner first(options), second(options);
  LocalPath a, b, other;
  LocalPlanStats sa, sb;
  ASSERT_TRUE(first.Plan(Pose2D{0, 0, 0}, Pose2D{3, 0, 0}, grid, &a, &sa));
  // Other plans in between (the streams are not shared between plans).
  for (int i = 0; i < 3; ++i) second.Plan(Pose2D{0, 0.3 * i, 0}, Pose2D{3, 1, 0}, grid, &other);
  ASSERT_TRUE(second.Plan(Pose2D{0, 0, 0}, Pose2D{3, 0, 0}, grid, &b, &sb));
  EXPECT_FALSE(sa.time_cap_hit);
  EXPECT_GT(sa.state_checks, 0);
  EXPECT_EQ(sa.state_checks, sb.state_checks);
  ASSERT_EQ(a.points_m.size(), b.points_m.size());
  for (size_t i = 0; i < a.points_m.size(); ++i) EXPECT_EQ(a.points_m[i], b.points_m[i]) << i;
  // Another seed samples differently (the test would not notice a constant plan otherwise).
  options.seed = 7;
  LocalPath c;
  LocalPlanStats sc;
  ASSERT_TRUE(LocalPlanner(options).Plan(Pose2D{0, 0, 0}, Pose2D{3, 0, 0}, grid, &c, &sc));
  EXPECT_NE(sc.state_checks, sa.state_checks);
}

TEST(LocalPlannerTest, WorkBudgetAndTimeCapEndPlanningWithReasons) {
  ObstacleGrid grid;
  grid.AddPoints(At(0), Eigen::Vector2d(1.5, 0), WallWithGap(10.0, 10.0));
  LocalPlannerOptions options;
  options.window_m = 5.0;  // closed wall: planning runs until it is stopped
  options.max_state_checks = 3000;
  LocalPath path;
  LocalPlanStats stats;
  Status s = LocalPlanner(options).Plan(Pose2D{0, 0, 0}, Pose2D{3, 0, 0}, grid, &path, &stats);
  ASSERT_FALSE(s.ok());
  EXPECT_NE(s.reason().find("3000 state checks"), std::string::npos) << s.reason();
  EXPECT_FALSE(stats.time_cap_hit);
  EXPECT_GE(stats.state_checks, 3000);
  EXPECT_LT(stats.state_checks, 3100);  // stops within an extension of the budget
  options.max_state_checks = 10000000;
  options.time_cap_ms = 5.0;
  s = LocalPlanner(options).Plan(Pose2D{0, 0, 0}, Pose2D{3, 0, 0}, grid, &path, &stats);
  ASSERT_FALSE(s.ok());
  EXPECT_TRUE(stats.time_cap_hit);
  EXPECT_NE(s.reason().find("5 ms time cap"), std::string::npos) << s.reason();
}

TEST(LocalPlannerTest, ResamplesPolylines) {
  const std::vector<Eigen::Vector2d> l{{0, 0}, {1, 0}, {1, 1}};
  const auto r = ResamplePolyline(l, 0.1);
  EXPECT_NEAR(PolylineLength(l), 2.0, 1e-12);
  EXPECT_NEAR(PolylineLength(r), 2.0, 0.03);
  EXPECT_EQ(r.size(), 21u);
  for (size_t i = 1; i < r.size(); ++i) EXPECT_LE((r[i] - r[i - 1]).norm(), 0.1 + 1e-9);
  EXPECT_LT((r.back() - l.back()).norm(), 1e-12);
}

}  // namespace
}  // namespace icgm
