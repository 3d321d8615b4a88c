// Runs the navigation nodelet on a hybrid map built offline from the simulated loop: with the
// robot (static tf map -> base_link) at one keyframe and a goal near another, the published route
// must be Dijkstra's route between the nearest keyframes (same nodes, same length as the core
// planner on the same map, consecutive poses joined by map links). Goals without a robot pose or
// far from the map give an empty route; an instance started on a file that is not a map keeps
// running, answers with errors and recovers on `~reload_map`.
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <set>
#include <string>
#include <utility>
#include <vector>

#include <unistd.h>

#include <geometry_msgs/PoseStamped.h>
#include <geometry_msgs/TransformStamped.h>
#include <gtest/gtest.h>
#include <icgm_slam/PlanRoute.h>
#include <nav_msgs/Path.h>
#include <ros/ros.h>
#include <ros/service.h>
#include <std_srvs/Trigger.h>
#include <tf2_ros/static_transform_broadcaster.h>
#include <visualization_msgs/MarkerArray.h>

#include "bag_replayer.h"
#include "core/map/map_store.h"
#include "core/nav/graph_planner.h"

namespace icgm_slam::test {
namespace {

constexpr double kTimeoutS = 10.0;

std::string MapPath() {
  std::string path;
  ros::NodeHandle("~").getParam("map", path);
  return path;
}

// Latest message on a topic, with a counter to wait for the next one.
template <typename Msg>
struct Latest {
  Latest(ros::NodeHandle& nh, const std::string& topic)
      : sub(nh.subscribe<Msg>(topic, 5, [this](const typename Msg::ConstPtr& m) {
          msg = m;
          ++count;
        })) {}
  // Spins until a message newer than the `seen`-th arrives.
  bool WaitBeyond(int seen) {
    const ros::WallTime end = ros::WallTime::now() + ros::WallDuration(kTimeoutS);
    while (count <= seen && ros::WallTime::now() < end) {
      ros::spinOnce();
      ros::WallDuration(0.01).sleep();
    }
    return count > seen;
  }
  typename Msg::ConstPtr msg;
  int count = 0;
  ros::Subscriber sub;
};

geometry_msgs::PoseStamped Goal(double x, double y) {
  geometry_msgs::PoseStamped goal;
  goal.header.frame_id = "map";
  goal.header.stamp = ros::Time::now();
  goal.pose.position.x = x;
  goal.pose.position.y = y;
  goal.pose.orientation.w = 1.0;  // on the floor (z = 0), as rviz sends it
  return goal;
}

// Publishes `goal` and returns the route answered on `route` (null on timeout).
nav_msgs::Path::ConstPtr SendGoal(ros::Publisher& pub, Latest<nav_msgs::Path>& route,
                                  const geometry_msgs::PoseStamped& goal) {
  const int seen = route.count;
  pub.publish(goal);
  return route.WaitBeyond(seen) ? route.msg : nullptr;
}

ros::Publisher GoalPublisher(ros::NodeHandle& nh, const std::string& topic) {
  ros::Publisher pub = nh.advertise<geometry_msgs::PoseStamped>(topic, 1);
  EXPECT_TRUE(WaitForSubscribers({pub}, 30.0)) << "nobody subscribes " << topic;
  ros::WallDuration(0.3).sleep();  // let the connection settle before the first message
  return pub;
}

TEST(Navigation, PublishesTheDijkstraRouteFromTheRobotToTheGoal) {
  ros::NodeHandle nh;
  const icgm::HybridMap map = icgm::LoadMap(MapPath());
  const icgm::GraphPlanner graph = icgm::GraphPlanner::FromMap(map);
  ASSERT_GE(map.size(), 10);
  std::set<std::pair<int, int>> links;
  for (const icgm::Link& l : map.links()) {
    links.insert({l.from_id, l.to_id});
    links.insert({l.to_id, l.from_id});
  }

  Latest<nav_msgs::Path> route(nh, "/icgm/route");
  Latest<visualization_msgs::MarkerArray> markers(nh, "/icgm/route/markers");
  ros::Publisher goal_pub = GoalPublisher(nh, "/move_base_simple/goal");

  // Robot at one keyframe of the first lap, goal beside a keyframe half a lap further on (the
  // map holds two laps of the loop).
  const int start_kf = map.size() / 8;
  const int goal_kf = map.size() * 3 / 8;
  const icgm::Vec3 robot = graph.position(start_kf);
  const icgm::Vec3 goal_xy = graph.position(goal_kf) + icgm::Vec3(0.1, -0.05, 0.0);

  // No robot pose on tf yet: no route.
  auto path = SendGoal(goal_pub, route, Goal(goal_xy.x(), goal_xy.y()));
  ASSERT_TRUE(path) << "no route published";
  EXPECT_TRUE(path->poses.empty()) << "route without a robot pose";

  tf2_ros::StaticTransformBroadcaster tf;
  geometry_msgs::TransformStamped t;
  t.header.stamp = ros::Time::now();
  t.header.frame_id = "map";
  t.child_frame_id = "base_link";
  t.transform.translation.x = robot.x();
  t.transform.translation.y = robot.y();
  t.transform.translation.z = robot.z();
  t.transform.rotation.w = 1.0;
  tf.sendTransform(t);
  ros::WallDuration(0.5).sleep();

  const int markers_seen = markers.count;
  path = SendGoal(goal_pub, route, Goal(goal_xy.x(), goal_xy.y()));
  ASSERT_TRUE(path) << "no route published";

  // Expected: Dijkstra between the nearest keyframes, on the same map.
  const int from = graph.NearestNode(robot);
  const int to = graph.NearestNode(icgm::Vec3(goal_xy.x(), goal_xy.y(), 0.0));
  icgm::Route expected;
  ASSERT_TRUE(graph.PlanRoute(from, to, &expected));
  std::printf("map: %d keyframes, %zu links; route %d -> %d: %zu keyframes, %.2f m\n", map.size(),
              map.links().size(), from, to, expected.nodes.size(), expected.length_m);
  ASSERT_GE(expected.nodes.size(), 3u);

  EXPECT_EQ(path->header.frame_id, "map");
  ASSERT_EQ(path->poses.size(), expected.nodes.size());
  double length = 0.0;
  int previous = -1;
  for (size_t i = 0; i < path->poses.size(); ++i) {
    const auto& p = path->poses[i].pose.position;
    const icgm::Vec3 position(p.x, p.y, p.z);
    const int node = graph.NearestNode(position);
    ASSERT_LT((graph.position(node) - position).norm(), 1e-9) << "pose " << i << " is no keyframe";
    EXPECT_EQ(node, expected.nodes[i]) << "pose " << i;
    if (previous >= 0) {
      EXPECT_TRUE(links.count({previous, node}))
          << "poses " << i - 1 << ", " << i << ": keyframes " << previous << " and " << node
          << " are not linked in the map";
      length += (graph.position(node) - graph.position(previous)).norm();
    }
    previous = node;
  }
  EXPECT_EQ(graph.NearestNode(icgm::Vec3(path->poses.front().pose.position.x,
                                         path->poses.front().pose.position.y,
                                         path->poses.front().pose.position.z)),
            from);
  EXPECT_EQ(previous, to);
  EXPECT_NEAR(length, expected.length_m, 1e-6);

  ASSERT_TRUE(markers.WaitBeyond(markers_seen)) << "no route markers";
  ASSERT_FALSE(markers.msg->markers.empty());
  EXPECT_EQ(markers.msg->markers[0].points.size(), expected.nodes.size());

  // The plan service gives the same route without tf.
  icgm_slam::PlanRoute plan;
  plan.request.start.x = robot.x();
  plan.request.start.y = robot.y();
  plan.request.start.z = robot.z();
  plan.request.goal.x = goal_xy.x();
  plan.request.goal.y = goal_xy.y();
  ASSERT_TRUE(ros::service::waitForService("/navigation/plan", 5000));
  ASSERT_TRUE(ros::service::call("/navigation/plan", plan));
  ASSERT_TRUE(plan.response.success) << plan.response.message;
  EXPECT_EQ(std::vector<int>(plan.response.keyframe_ids.begin(), plan.response.keyframe_ids.end()),
            expected.nodes);
  EXPECT_NEAR(plan.response.length_m, expected.length_m, 1e-9);
  EXPECT_EQ(plan.response.path.poses.size(), expected.nodes.size());

  // A goal far from every keyframe: no route, an empty path, markers cleared.
  path = SendGoal(goal_pub, route, Goal(100.0, 100.0));
  ASSERT_TRUE(path);
  EXPECT_TRUE(path->poses.empty());
  plan.request.start_from_robot = true;
  plan.request.goal.x = plan.request.goal.y = 100.0;
  ASSERT_TRUE(ros::service::call("/navigation/plan", plan));
  EXPECT_FALSE(plan.response.success);
  EXPECT_NE(plan.response.message.find("goal_tolerance_m"), std::string::npos)
      << plan.response.message;
}

TEST(Navigation, SurvivesMissingAndCorruptMaps) {
  ros::NodeHandle nh;
  const std::string good = MapPath();
  const icgm::GraphPlanner graph = icgm::GraphPlanner::FromMap(icgm::LoadMap(good));
  const icgm::Vec3 a = graph.position(0), b = graph.position(graph.size() / 2);

  // Started on a file that is not a map: goals get an empty route, plans an error.
  Latest<nav_msgs::Path> route(nh, "/bad/route");
  ros::Publisher goal_pub = GoalPublisher(nh, "/bad/goal");
  const auto path = SendGoal(goal_pub, route, Goal(b.x(), b.y()));
  ASSERT_TRUE(path) << "no route published";
  EXPECT_TRUE(path->poses.empty());

  icgm_slam::PlanRoute plan;
  plan.request.start.x = a.x();
  plan.request.start.y = a.y();
  plan.request.goal.x = b.x();
  plan.request.goal.y = b.y();
  ASSERT_TRUE(ros::service::waitForService("/navigation_bad/plan", 5000));
  ASSERT_TRUE(ros::service::call("/navigation_bad/plan", plan));
  EXPECT_FALSE(plan.response.success);
  EXPECT_NE(plan.response.message.find("no map loaded"), std::string::npos)
      << plan.response.message;

  // A truncated copy of a real map and a missing file are refused on reload, without a crash.
  const std::string truncated = (std::filesystem::temp_directory_path() /
                                 ("icgm_nav_truncated_" + std::to_string(::getpid()) + ".db"))
                                    .string();
  {
    std::ifstream in(good, std::ios::binary);
    std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    ASSERT_GT(bytes.size(), 8192u);
    std::ofstream(truncated, std::ios::binary).write(bytes.data(), bytes.size() / 2);
  }
  for (const std::string& bad : {truncated, truncated + ".missing"}) {
    nh.setParam("/navigation_bad/map_path", bad);
    std_srvs::Trigger reload;
    ASSERT_TRUE(ros::service::call("/navigation_bad/reload_map", reload)) << bad;
    EXPECT_FALSE(reload.response.success) << bad;
    std::printf("reload %s: %s\n", bad.c_str(), reload.response.message.c_str());
    EXPECT_FALSE(reload.response.message.empty());
    ASSERT_TRUE(ros::service::call("/navigation_bad/plan", plan)) << "nodelet gone after " << bad;
    EXPECT_FALSE(plan.response.success);
  }
  std::filesystem::remove(truncated);

  // Still alive: reloading the good map makes it plan.
  nh.setParam("/navigation_bad/map_path", good);
  std_srvs::Trigger reload;
  ASSERT_TRUE(ros::service::call("/navigation_bad/reload_map", reload));
  EXPECT_TRUE(reload.response.success) << reload.response.message;
  ASSERT_TRUE(ros::service::call("/navigation_bad/plan", plan));
  EXPECT_TRUE(plan.response.success) << plan.response.message;
  EXPECT_FALSE(plan.response.keyframe_ids.empty());
}

}  // namespace
}  // namespace icgm_slam::test

int main(int argc, char** argv) {
  testing::InitGoogleTest(&argc, argv);
  ros::init(argc, argv, "navigation_rostest");
  return RUN_ALL_TESTS();
}
