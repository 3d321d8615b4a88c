// The navigation nodelet's action server on a hybrid map built offline from the simulated loop,
// without a simulator: the test gives tf (map -> odom -> base_link at a keyframe, base -> camera)
// and no depth. A goal near another keyframe is accepted and its route (nav_msgs/Path) runs from
// the robot through Dijkstra's keyframes (taken in base positions) to the goal itself; with no
// depth arriving the goal is then ABORTED with the reason, and the last Twist is zero. Goals off
// the map, in a frame on no tf, for a robot on no tf and on a nodelet without a map are ABORTED
// with their reasons; a nodelet started on a file that is not a map keeps running, refuses
// corrupt maps on ~reload_map and navigates after reloading a good one.
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <functional>
#include <iterator>
#include <string>
#include <vector>

#include <unistd.h>

#include <actionlib/client/simple_action_client.h>
#include <geometry_msgs/TransformStamped.h>
#include <geometry_msgs/Twist.h>
#include <gtest/gtest.h>
#include <move_base_msgs/MoveBaseAction.h>
#include <nav_msgs/Path.h>
#include <ros/ros.h>
#include <ros/service.h>
#include <std_srvs/Trigger.h>
#include <tf2_ros/static_transform_broadcaster.h>

#include "core/map/map_store.h"
#include "core/nav/graph_planner.h"
#include "ros_bridge/conversions.h"

namespace icgm_slam::test {
namespace {

using Client = actionlib::SimpleActionClient<move_base_msgs::MoveBaseAction>;
using State = actionlib::SimpleClientGoalState;

std::string MapPath() {
  std::string path;
  ros::NodeHandle("~").getParam("map", path);
  return path;
}

bool SpinUntil(const std::function<bool()>& done, double timeout_s) {
  const ros::WallTime end = ros::WallTime::now() + ros::WallDuration(timeout_s);
  while (!done() && ros::WallTime::now() < end) {
    ros::spinOnce();
    ros::WallDuration(0.01).sleep();
  }
  return done();
}

// A camera mount like the simulator's: 1 m up, 0.1 m forward, optical axes (z forward).
icgm::Pose3 BaseToCamera() {
  Eigen::Matrix3d R;
  R << 0, 0, 1, -1, 0, 0, 0, -1, 0;
  return icgm::MakePose({0.1, 0.0, 1.0}, icgm::Quat(R));
}

geometry_msgs::TransformStamped Transform(const std::string& parent, const std::string& child,
                                          const icgm::Pose3& pose) {
  geometry_msgs::TransformStamped t;
  t.header.stamp = ros::Time::now();
  t.header.frame_id = parent;
  t.child_frame_id = child;
  t.transform = icgm::ros_bridge::ToTransformMsg(pose);
  return t;
}

move_base_msgs::MoveBaseGoal Goal(double x, double y, const std::string& frame = "map") {
  move_base_msgs::MoveBaseGoal goal;
  goal.target_pose.header.frame_id = frame;
  goal.target_pose.header.stamp = ros::Time::now();
  goal.target_pose.pose.position.x = x;
  goal.target_pose.pose.position.y = y;
  goal.target_pose.pose.orientation.w = 1.0;
  return goal;
}

// Sends `goal` and waits for its end; returns the final state (its text: the reason).
State RunGoal(Client& client, const move_base_msgs::MoveBaseGoal& goal, double timeout_s = 20.0) {
  client.sendGoal(goal);
  SpinUntil([&] { return client.getState().isDone(); }, timeout_s);
  const State s = client.getState();
  std::printf("goal (%.1f, %.1f) in '%s': %s, '%s'\n", goal.target_pose.pose.position.x,
              goal.target_pose.pose.position.y, goal.target_pose.header.frame_id.c_str(),
              s.toString().c_str(), s.getText().c_str());
  return s;
}

bool Connect(Client& client) {
  return SpinUntil([&] { return client.isServerConnected(); }, 30.0);
}

// Base positions of the map's keyframes (keyframe poses are camera poses) as a graph with the
// map's links: what the navigator plans on.
icgm::GraphPlanner BaseGraph(const icgm::HybridMap& map) {
  icgm::GraphPlanner g;
  for (const auto& kf : map.keyframes()) {
    g.AddNode((kf.global_pose * BaseToCamera().inverse()).translation());
  }
  for (const auto& l : map.links()) EXPECT_TRUE(g.AddEdge(l.from_id, l.to_id).ok());
  return g;
}

double DistanceToPath(const nav_msgs::Path& path, const icgm::Vec3& p) {
  double best = 1e9;
  for (const auto& q : path.poses) {
    best = std::min(best, std::hypot(q.pose.position.x - p.x(), q.pose.position.y - p.y()));
  }
  return best;
}

TEST(Navigation, RoutesThroughTheMapAndAbortsWithReasons) {
  ros::NodeHandle nh;
  const icgm::HybridMap map = icgm::LoadMap(MapPath());
  ASSERT_GE(map.size(), 10);
  const icgm::GraphPlanner graph = BaseGraph(map);
  const int start_kf = map.size() / 8, goal_kf = map.size() * 3 / 8;
  const icgm::Vec3 robot = graph.position(start_kf);
  const icgm::Vec3 goal = graph.position(goal_kf) + icgm::Vec3(0.1, -0.05, 0.0);

  nav_msgs::Path::ConstPtr route;
  ros::Subscriber route_sub = nh.subscribe<nav_msgs::Path>(
      "/icgm/route", 1, [&](const nav_msgs::Path::ConstPtr& m) { route = m; });
  geometry_msgs::Twist::ConstPtr last_cmd;
  ros::Subscriber cmd_sub = nh.subscribe<geometry_msgs::Twist>(
      "/cmd_vel", 50, [&](const geometry_msgs::Twist::ConstPtr& m) { last_cmd = m; });
  Client client(nh, "move_base", false);
  ASSERT_TRUE(Connect(client));

  // No robot on tf yet: aborted once ~pose_wait_s (1 s) has passed.
  State s = RunGoal(client, Goal(goal.x(), goal.y()));
  EXPECT_EQ(s, State::ABORTED);
  EXPECT_NE(s.getText().find("no robot pose"), std::string::npos) << s.getText();

  tf2_ros::StaticTransformBroadcaster tf;
  const icgm::Pose3 map_base = icgm::MakePose(robot, icgm::Quat::Identity());
  tf.sendTransform({Transform("map", "odom", icgm::Pose3::Identity()),
                    Transform("odom", "base_link", map_base),
                    Transform("base_link", "camera_rgb_optical_frame", BaseToCamera())});
  ros::WallDuration(0.5).sleep();

  // A goal beside a keyframe: the route runs from the robot's keyframe through Dijkstra's
  // keyframes to the goal itself. No depth ever arrives: aborted with the reason.
  route.reset();
  last_cmd.reset();
  s = RunGoal(client, Goal(goal.x(), goal.y()));
  ASSERT_TRUE(SpinUntil([&] { return route != nullptr; }, 2.0)) << "no route published";
  icgm::Route expected;
  ASSERT_TRUE(graph.PlanRoute(graph.NearestNode(robot), graph.NearestNode(goal), &expected).ok());
  ASSERT_GE(expected.nodes.size(), 3u);
  EXPECT_EQ(route->header.frame_id, "map");
  ASSERT_GE(route->poses.size(), 2u);
  const auto& end = route->poses.back().pose.position;
  EXPECT_NEAR(end.x, goal.x(), 1e-6);
  EXPECT_NEAR(end.y, goal.y(), 1e-6);
  for (int node : expected.nodes) {
    EXPECT_LT(DistanceToPath(*route, graph.position(node)), 0.06) << "keyframe " << node;
  }
  std::printf("route: %zu points, %zu keyframes on it\n", route->poses.size(),
              expected.nodes.size());
  EXPECT_EQ(s, State::ABORTED);
  EXPECT_NE(s.getText().find("depth"), std::string::npos) << s.getText();
  ASSERT_TRUE(last_cmd);
  EXPECT_EQ(last_cmd->linear.x, 0.0);
  EXPECT_EQ(last_cmd->angular.z, 0.0);

  // A goal that is no pose: aborted at once, naming what is wrong (the base stops).
  move_base_msgs::MoveBaseGoal nan_goal = Goal(goal.x(), goal.y());
  nan_goal.target_pose.pose.position.x = std::nan("");
  s = RunGoal(client, nan_goal, 2.0);
  EXPECT_EQ(s, State::ABORTED);
  EXPECT_NE(s.getText().find("goal position (nan"), std::string::npos) << s.getText();
  move_base_msgs::MoveBaseGoal zero_quaternion = Goal(goal.x(), goal.y());
  zero_quaternion.target_pose.pose.orientation.w = 0.0;
  s = RunGoal(client, zero_quaternion, 2.0);
  EXPECT_EQ(s, State::ABORTED);
  EXPECT_NE(s.getText().find("not a quaternion"), std::string::npos) << s.getText();

  // A goal sent while another is active preempts it, and the first one's text says so.
  Client second(nh, "move_base", false);
  ASSERT_TRUE(Connect(second));
  client.sendGoal(Goal(goal.x(), goal.y()));
  ASSERT_TRUE(SpinUntil([&] { return client.getState() == State::ACTIVE; }, 5.0));
  second.sendGoal(Goal(goal.x(), goal.y()));
  ASSERT_TRUE(SpinUntil([&] { return client.getState().isDone(); }, 5.0));
  EXPECT_EQ(client.getState(), State::PREEMPTED);
  EXPECT_EQ(client.getState().getText(), "preempted by a newer goal");
  ASSERT_TRUE(SpinUntil([&] { return second.getState() == State::ACTIVE; }, 5.0));
  second.cancelGoal();
  ASSERT_TRUE(SpinUntil([&] { return second.getState().isDone(); }, 5.0));
  EXPECT_EQ(second.getState(), State::PREEMPTED);
  EXPECT_EQ(second.getState().getText(), "cancelled");

  // Off the map, and in a frame on no tf.
  s = RunGoal(client, Goal(100.0, 100.0));
  EXPECT_EQ(s, State::ABORTED);
  EXPECT_FALSE(s.getText().empty());
  s = RunGoal(client, Goal(goal.x(), goal.y(), "frame_on_no_tf"));
  EXPECT_EQ(s, State::ABORTED);
  EXPECT_NE(s.getText().find("frame_on_no_tf"), std::string::npos) << s.getText();

  // A nodelet whose base frame is on no tf.
  Client notf(nh, "/notf/move_base", false);
  ASSERT_TRUE(Connect(notf));
  s = RunGoal(notf, Goal(goal.x(), goal.y()));
  EXPECT_EQ(s, State::ABORTED);
  EXPECT_NE(s.getText().find("base_link_on_no_tf"), std::string::npos) << s.getText();
}

TEST(Navigation, SurvivesMissingAndCorruptMaps) {
  ros::NodeHandle nh;
  const std::string good = MapPath();
  Client client(nh, "/bad/move_base", false);
  ASSERT_TRUE(Connect(client));
  State s = RunGoal(client, Goal(1.0, 1.0));
  EXPECT_EQ(s, State::ABORTED);
  EXPECT_NE(s.getText().find("no map"), std::string::npos) << s.getText();

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
    nh.setParam("/bad/navigation/map_path", bad);
    std_srvs::Trigger reload;
    ASSERT_TRUE(ros::service::call("/bad/navigation/reload_map", reload)) << bad;
    EXPECT_FALSE(reload.response.success) << bad;
    std::printf("reload %s: %s\n", bad.c_str(), reload.response.message.c_str());
    EXPECT_FALSE(reload.response.message.empty());
    s = RunGoal(client, Goal(1.0, 1.0));
    EXPECT_EQ(s, State::ABORTED) << "nodelet gone after " << bad;
    EXPECT_NE(s.getText().find("no map"), std::string::npos) << s.getText();
  }
  std::filesystem::remove(truncated);

  // Still alive: with the good map reloaded, a goal far off it is refused for that reason.
  nh.setParam("/bad/navigation/map_path", good);
  std_srvs::Trigger reload;
  ASSERT_TRUE(ros::service::call("/bad/navigation/reload_map", reload));
  EXPECT_TRUE(reload.response.success) << reload.response.message;
  s = RunGoal(client, Goal(100.0, 100.0));
  EXPECT_EQ(s, State::ABORTED);
  EXPECT_EQ(s.getText().find("no map"), std::string::npos) << s.getText();
}

}  // namespace
}  // namespace icgm_slam::test
