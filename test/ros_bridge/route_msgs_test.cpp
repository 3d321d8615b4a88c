#include "ros_bridge/route_msgs.h"

#include <cmath>

#include <gtest/gtest.h>

namespace icgm::ros_bridge {
namespace {

TEST(RouteMsgsTest, PathFollowsTheRouteWithHeadings) {
  GraphPlanner g;
  g.AddNode({0, 0, 0.5});
  g.AddNode({1, 0, 0.5});
  g.AddNode({1, 2, 0.5});
  ASSERT_TRUE(g.AddEdge(0, 1));
  ASSERT_TRUE(g.AddEdge(1, 2));
  Route route;
  ASSERT_TRUE(g.PlanRoute(0, 2, &route));
  const nav_msgs::Path path = ToRoutePath(g, route, "map", Time::FromSeconds(2));
  EXPECT_EQ(path.header.frame_id, "map");
  ASSERT_EQ(path.poses.size(), 3u);
  EXPECT_DOUBLE_EQ(path.poses[1].pose.position.x, 1.0);
  EXPECT_DOUBLE_EQ(path.poses[2].pose.position.y, 2.0);
  EXPECT_DOUBLE_EQ(path.poses[2].pose.position.z, 0.5);
  EXPECT_EQ(path.poses[2].header.frame_id, "map");
  // Heading +x on the first segment, +y on the second and at the goal.
  EXPECT_NEAR(path.poses[0].pose.orientation.w, 1.0, 1e-12);
  EXPECT_NEAR(path.poses[1].pose.orientation.z, std::sin(M_PI / 4), 1e-12);
  EXPECT_NEAR(path.poses[2].pose.orientation.z, std::sin(M_PI / 4), 1e-12);

  const auto markers = ToRouteMarkers(g, route, "map", Time::FromSeconds(2));
  ASSERT_EQ(markers.markers.size(), 2u);
  EXPECT_EQ(markers.markers[0].type, visualization_msgs::Marker::LINE_STRIP);
  EXPECT_EQ(markers.markers[0].points.size(), 3u);
  EXPECT_EQ(markers.markers[1].action, visualization_msgs::Marker::ADD);
  EXPECT_DOUBLE_EQ(markers.markers[1].pose.position.y, 2.0);
}

TEST(RouteMsgsTest, EmptyRouteClearsTheMarkers) {
  GraphPlanner g;
  g.AddNode({0, 0, 0});
  const Route empty;
  EXPECT_TRUE(ToRoutePath(g, empty, "map", Time()).poses.empty());
  const auto markers = ToRouteMarkers(g, empty, "map", Time());
  ASSERT_EQ(markers.markers.size(), 2u);
  for (const auto& m : markers.markers) EXPECT_EQ(m.action, visualization_msgs::Marker::DELETE);
}

}  // namespace
}  // namespace icgm::ros_bridge
