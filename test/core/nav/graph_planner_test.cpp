#include "core/nav/graph_planner.h"

#include <gtest/gtest.h>

namespace icgm {
namespace {

// Hand-built graph (positions in metres):
//   0(0,0) -- 1(1,0) -- 2(2,0) -- 3(3,0)
//    \                            /
//     4(0,2) ------- 5(3,2) -----
// plus a long detour 1 -- 6(1,5) -- 3, and an isolated node 7.
GraphPlanner MakeGraph() {
  GraphPlanner g;
  for (const auto& p :
       {Eigen::Vector3d(0, 0, 0), Eigen::Vector3d(1, 0, 0), Eigen::Vector3d(2, 0, 0),
        Eigen::Vector3d(3, 0, 0), Eigen::Vector3d(0, 2, 0), Eigen::Vector3d(3, 2, 0),
        Eigen::Vector3d(1, 5, 0), Eigen::Vector3d(9, 9, 0)}) {
    g.AddNode(p);
  }
  for (const auto& [a, b] : std::vector<std::pair<int, int>>{
           {0, 1}, {1, 2}, {2, 3}, {0, 4}, {4, 5}, {5, 3}, {1, 6}, {6, 3}}) {
    EXPECT_TRUE(g.AddEdge(a, b));
  }
  return g;
}

TEST(GraphPlannerTest, FindsTheKnownShortestPath) {
  const GraphPlanner g = MakeGraph();
  Route r;
  ASSERT_TRUE(g.PlanRoute(0, 3, &r));
  EXPECT_EQ(r.nodes, (std::vector<int>{0, 1, 2, 3}));
  EXPECT_NEAR(r.length_m, 3.0, 1e-12);
  ASSERT_TRUE(g.PlanRoute(4, 2, &r));
  // 4-0-1-2 = 2 + 1 + 1 = 4 beats 4-5-3-2 = 3 + 2 + 1 = 6.
  EXPECT_EQ(r.nodes, (std::vector<int>{4, 0, 1, 2}));
  EXPECT_NEAR(r.length_m, 4.0, 1e-12);
  ASSERT_TRUE(g.PlanRoute(5, 5, &r));
  EXPECT_EQ(r.nodes, (std::vector<int>{5}));
  EXPECT_EQ(r.length_m, 0.0);
}

TEST(GraphPlannerTest, ExplicitLengthsOverrideGeometry) {
  GraphPlanner g = MakeGraph();
  ASSERT_TRUE(g.AddEdge(0, 3, 0.5));  // e.g. a shortcut known to be short
  Route r;
  ASSERT_TRUE(g.PlanRoute(4, 3, &r));
  EXPECT_EQ(r.nodes, (std::vector<int>{4, 0, 3}));
  EXPECT_NEAR(r.length_m, 2.5, 1e-12);
}

TEST(GraphPlannerTest, UnreachableOrUnknownGoalIsAStatusWithReason) {
  GraphPlanner g = MakeGraph();
  Route r;
  Status s = g.PlanRoute(0, 7, &r);
  EXPECT_FALSE(s.ok());
  EXPECT_NE(s.reason().find("unreachable"), std::string::npos);
  s = g.PlanRoute(0, 42, &r);
  EXPECT_FALSE(s.ok());
  EXPECT_NE(s.reason().find("42"), std::string::npos);
  EXPECT_FALSE(g.PlanRoute(-1, 0, &r).ok());
  EXPECT_FALSE(g.AddEdge(0, 8).ok());
  EXPECT_EQ(g.NearestNode(Eigen::Vector3d(2.9, 1.8, 0)), 5);
  EXPECT_EQ(GraphPlanner().NearestNode(Eigen::Vector3d::Zero()), -1);
}

TEST(GraphPlannerTest, MapGraphUsesOdometryAndLoopLinks) {
  // Out along x and back: keyframe 9 is next to keyframe 0; a loop link joins them.
  HybridMap map;
  int id = -1;
  const Pose3 forward = MakePose(Vec3(1, 0, 0), Quat::Identity());
  const Pose3 turn = MakePose(Vec3(0, 0, 0), Quat(Eigen::AngleAxisd(M_PI, Vec3::UnitZ())));
  for (int k = 0; k < 10; ++k) {
    Keyframe kf;
    kf.relative_pose = k == 0 ? Pose3::Identity() : (k == 5 ? forward * turn : forward);
    ASSERT_TRUE(map.AddKeyframe(kf, Mat6::Identity(), &id));
  }
  Route r;
  GraphPlanner without = GraphPlanner::FromMap(map);
  ASSERT_TRUE(without.PlanRoute(0, 9, &r));
  EXPECT_EQ(r.nodes.size(), 10u);
  Link loop;
  loop.from_id = 0;
  loop.to_id = 9;
  loop.type = LinkType::kLoopClosure;
  ASSERT_TRUE(map.AddLink(loop));
  ASSERT_TRUE(GraphPlanner::FromMap(map).PlanRoute(0, 9, &r));
  EXPECT_EQ(r.nodes, (std::vector<int>{0, 9}));
  EXPECT_NEAR(r.length_m, 1.0, 1e-9);
}

}  // namespace
}  // namespace icgm
