// Closed-loop navigation through the nodelets (navigation_sim.test): the simulator nodelet drives
// the robot by /cmd_vel in the small loop's world with three walkers, the pipeline localizes on
// the loop's learned map, the navigation nodelet follows goals. Checked against the simulator's
// ground truth (sim/status): a move_base goal a few metres along the learned loop ends
// SUCCEEDED with the true base near the goal and no contact with furniture, walls or walkers;
// a goal on /move_base_simple/goal sets the robot moving, and cancelling it gives a zero Twist
// within 0.5 s; a goal far off the map is ABORTED with the reason as the result text.
//
// The learned map's frame is the teach run's odom frame, base_link where that run started; the
// simulator starts the robot there too, so the world -> map transform is the true start pose
// (checked: the localized start pose must agree with it).
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <functional>
#include <limits>
#include <string>
#include <vector>

#include <actionlib/client/simple_action_client.h>
#include <actionlib_msgs/GoalStatusArray.h>
#include <geometry_msgs/PoseStamped.h>
#include <geometry_msgs/Twist.h>
#include <gtest/gtest.h>
#include <icgm_slam/SimStatus.h>
#include <move_base_msgs/MoveBaseAction.h>
#include <nav_msgs/Path.h>
#include <ros/ros.h>
#include <tf2_ros/buffer.h>
#include <tf2_ros/transform_listener.h>

#include "core/map/map_store.h"
#include "ros_bridge/conversions.h"

namespace icgm_slam::test {
namespace {

using Client = actionlib::SimpleActionClient<move_base_msgs::MoveBaseAction>;
namespace rb = icgm::ros_bridge;

bool SpinSimUntil(const std::function<bool()>& done, double timeout_s) {
  const ros::WallTime end = ros::WallTime::now() + ros::WallDuration(timeout_s);
  while (!done() && ros::WallTime::now() < end) {
    ros::spinOnce();
    ros::WallDuration(0.005).sleep();
  }
  return done();
}

// What the test watches: the simulator's ground truth and every command sent to the base.
struct Watch {
  explicit Watch(ros::NodeHandle& nh)
      : status_sub(nh.subscribe<icgm_slam::SimStatus>(
            "/sim/status", 100,
            [this](const icgm_slam::SimStatus::ConstPtr& m) {
              if (!first) first = m;
              status = m;
              steps.push_back({m->header.stamp.toSec(), BaseInWorld(), m->pedestrian_clearance_m});
            })),
        cmd_sub(nh.subscribe<geometry_msgs::Twist>("/cmd_vel", 100,
                                                   [this](const geometry_msgs::Twist::ConstPtr& m) {
                                                     cmds.push_back({ros::WallTime::now(), *m});
                                                   })),
        route_sub(nh.subscribe<nav_msgs::Path>(
            "/icgm/route", 10, [this](const nav_msgs::Path::ConstPtr& m) { route = m; })) {}
  icgm::Vec3 BaseInWorld() const { return rb::FromPoseMsg(status->base_pose).translation(); }
  int Collisions() const { return status->static_collisions + status->pedestrian_collisions; }

  icgm_slam::SimStatus::ConstPtr first, status;
  // After every step: the simulated time, the true base in the world, the footprint's clearance
  // from the nearest walker.
  struct Step {
    double stamp_s;
    icgm::Vec3 base;
    double walker_clearance_m;
  };
  std::vector<Step> steps;
  std::vector<std::pair<ros::WallTime, geometry_msgs::Twist>> cmds;
  nav_msgs::Path::ConstPtr route;  // the navigator's route (map frame), latched
  ros::Subscriber status_sub, cmd_sub, route_sub;
};

// Distance of `p` from the polyline through the route's poses.
double DistanceFromRoute(const nav_msgs::Path& route, const Eigen::Vector2d& p) {
  double best = std::numeric_limits<double>::infinity();
  for (size_t i = 0; i < route.poses.size(); ++i) {
    const Eigen::Vector2d a(route.poses[i].pose.position.x, route.poses[i].pose.position.y);
    const size_t j = std::min(i + 1, route.poses.size() - 1);
    const Eigen::Vector2d b(route.poses[j].pose.position.x, route.poses[j].pose.position.y);
    const Eigen::Vector2d ab = b - a;
    const double t =
        ab.squaredNorm() > 0.0 ? std::clamp((p - a).dot(ab) / ab.squaredNorm(), 0.0, 1.0) : 0.0;
    best = std::min(best, (a + t * ab - p).norm());
  }
  return best;
}

// A point on the learned loop about `ahead_m` along it from the first keyframe: a keyframe's
// base position in the map frame (keyframes are camera poses).
Eigen::Vector2d GoalAlongTheLoop(const icgm::HybridMap& map, const icgm::Pose3& T_base_camera,
                                 double ahead_m) {
  double along = 0.0;
  icgm::Vec3 previous = (map.keyframe(0).global_pose * T_base_camera.inverse()).translation();
  for (const auto& kf : map.keyframes()) {
    const icgm::Vec3 p = (kf.global_pose * T_base_camera.inverse()).translation();
    along += (p - previous).head<2>().norm();
    previous = p;
    if (along >= ahead_m) return p.head<2>();
  }
  return previous.head<2>();
}

move_base_msgs::MoveBaseGoal Goal(const Eigen::Vector2d& xy) {
  move_base_msgs::MoveBaseGoal goal;
  goal.target_pose.header.frame_id = "map";
  goal.target_pose.header.stamp = ros::Time::now();
  goal.target_pose.pose.position.x = xy.x();
  goal.target_pose.pose.position.y = xy.y();
  goal.target_pose.pose.orientation.w = 1.0;
  return goal;
}

TEST(NavigationSim, ReachesGoalsWithoutCollisionCancelsAndRefusesOffMapGoals) {
  ros::NodeHandle nh;
  std::string map_path;
  ASSERT_TRUE(ros::NodeHandle("~").getParam("map", map_path));
  const icgm::HybridMap map = icgm::LoadMap(map_path);
  ASSERT_GE(map.size(), 10);
  Watch watch(nh);
  tf2_ros::Buffer tf;
  tf2_ros::TransformListener listener(tf);
  Client client(nh, "move_base", false);

  ASSERT_TRUE(SpinSimUntil([&] { return client.isServerConnected() && watch.status; }, 60.0))
      << "no move_base server or no simulator";
  // Localized on the learned map (the robot stands still until it has a goal).
  ASSERT_TRUE(
      SpinSimUntil([&] { return tf.canTransform("map", "base_link", ros::Time(0)); }, 120.0))
      << "never localized (no tf map -> base_link)";
  const icgm::Pose3 T_base_camera = rb::FromTransformMsg(
      tf.lookupTransform("base_link", "camera_rgb_optical_frame", ros::Time(0)).transform);
  const icgm::Pose3 T_world_map = rb::FromPoseMsg(watch.first->base_pose);
  const icgm::Pose3 localized =
      rb::FromTransformMsg(tf.lookupTransform("map", "base_link", ros::Time(0)).transform);
  const icgm::Pose3 truth = T_world_map.inverse() * rb::FromPoseMsg(watch.status->base_pose);
  std::printf("localized start off the truth by %.3f m\n",
              (localized.translation() - truth.translation()).head<2>().norm());
  ASSERT_LT((localized.translation() - truth.translation()).head<2>().norm(), 0.3);

  // 1. A move_base goal 3.5 m along the loop (round its first corner).
  const Eigen::Vector2d goal_a = GoalAlongTheLoop(map, T_base_camera, 3.5);
  const double sim_start = watch.status->header.stamp.toSec();
  const size_t steps_before_a = watch.steps.size();
  // Feedback (the navigator's localized base) and the last command: what the robot was doing
  // when a goal did not end.
  geometry_msgs::PoseStamped feedback;
  int feedbacks = 0;
  // Sent again while the server has not taken it after 10 s, as a user sends a goal again: a
  // message sent on a connection just made can be lost on a loaded machine (see the simple goal
  // below); how often it took is printed.
  int goal_a_sends = 0;
  do {
    client.sendGoal(Goal(goal_a), Client::SimpleDoneCallback(), Client::SimpleActiveCallback(),
                    [&](const move_base_msgs::MoveBaseFeedback::ConstPtr& f) {
                      feedback = f->base_position;
                      ++feedbacks;
                    });
    ++goal_a_sends;
  } while (
      !SpinSimUntil([&] { return client.getState() != actionlib::SimpleClientGoalState::PENDING; },
                    10.0) &&
      goal_a_sends < 3);
  std::printf("goal A: taken by the server after %d send(s)\n", goal_a_sends);
  // The simulator waits for the pipeline, so a loaded machine stretches the wall time a goal
  // takes; the budget is simulated time (the goal takes 5-20 s of it), bounded in wall time.
  const double goal_a_budget_sim_s = 120.0;
  const bool goal_a_done = SpinSimUntil(
      [&] {
        return client.getState().isDone() ||
               watch.status->header.stamp.toSec() - sim_start > goal_a_budget_sim_s;
      },
      300.0);
  ASSERT_TRUE(goal_a_done && client.getState().isDone())
      << "goal A not done after " << watch.status->header.stamp.toSec() - sim_start
      << " s simulated (budget " << goal_a_budget_sim_s << " s; state "
      << client.getState().toString() << "): true base at (" << watch.BaseInWorld().x() << ", "
      << watch.BaseInWorld().y() << ") in the world, "
      << (watch.BaseInWorld() - T_world_map * icgm::Vec3(goal_a.x(), goal_a.y(), 0.0))
             .head<2>()
             .norm()
      << " m from the goal, driven " << watch.status->distance_driven_m << " m, moving at "
      << watch.status->linear_mps << " m/s; nearest walker " << watch.status->pedestrian_clearance_m
      << " m; " << feedbacks << " feedbacks, last at (" << feedback.pose.position.x << ", "
      << feedback.pose.position.y << ") in the map; " << watch.cmds.size()
      << " commands, last linear " << (watch.cmds.empty() ? 0.0 : watch.cmds.back().second.linear.x)
      << " m/s";
  EXPECT_EQ(client.getState(), actionlib::SimpleClientGoalState::SUCCEEDED)
      << client.getState().getText();
  const icgm::Vec3 goal_a_world = T_world_map * icgm::Vec3(goal_a.x(), goal_a.y(), 0.0);
  const double miss_m = (watch.BaseInWorld() - goal_a_world).head<2>().norm();
  std::printf(
      "goal A (%.2f, %.2f): %s after %.1f s simulated, %.2f m driven; true base %.3f m "
      "from the goal; collisions %d (min clearance furniture %.2f m, walkers %.2f m)\n",
      goal_a.x(), goal_a.y(), client.getState().getText().c_str(),
      watch.status->header.stamp.toSec() - sim_start, watch.status->distance_driven_m, miss_m,
      watch.Collisions(), watch.status->min_static_clearance_m,
      watch.status->min_pedestrian_clearance_m);
  const std::string goal_a_summary =
      "goal A: " + client.getState().getText() + "; driven " +
      std::to_string(watch.status->distance_driven_m) + " m; contacts furniture/walls " +
      std::to_string(watch.status->static_collisions) + ", walkers " +
      std::to_string(watch.status->pedestrian_collisions) + "; min clearance furniture " +
      std::to_string(watch.status->min_static_clearance_m) + " m, walkers " +
      std::to_string(watch.status->min_pedestrian_clearance_m) + " m";
  EXPECT_LT(miss_m, 0.5) << "the true base ended too far from the goal; " << goal_a_summary;
  // The true base's deviation from the route it followed, detours around walkers included (the
  // navigator starts a detour for a walker predicted to cross the route, often more than a metre
  // away, so the deviation away from walkers is printed, not bounded).
  constexpr double kNearWalkerM = 1.0, kAfterWalkerS = 2.0;
  ASSERT_TRUE(watch.route) << "no route published on /icgm/route";
  double away_max = 0.0, overall_max = 0.0, last_near_s = -1e9;
  int away_steps = 0;
  for (size_t i = steps_before_a; i < watch.steps.size(); ++i) {
    const Watch::Step& step = watch.steps[i];
    const double d = DistanceFromRoute(*watch.route, (T_world_map.inverse() * step.base).head<2>());
    overall_max = std::max(overall_max, d);
    if (step.walker_clearance_m < kNearWalkerM) last_near_s = step.stamp_s;
    if (step.stamp_s - last_near_s > kAfterWalkerS) {
      away_max = std::max(away_max, d);
      ++away_steps;
    }
  }
  std::printf(
      "goal A: true deviation from the route max %.3f m away from walkers (none within 1 m for 2 "
      "s: %d of %zu steps), "
      "max %.3f m overall\n",
      away_max, away_steps, watch.steps.size() - steps_before_a, overall_max);
  EXPECT_LT(overall_max, 1.5) << goal_a_summary;  // a detour may cut a corner: 1.11 m seen
  EXPECT_GT(watch.status->distance_driven_m, 2.5) << goal_a_summary;
  EXPECT_EQ(watch.Collisions(), 0) << goal_a_summary;

  // 2. /move_base_simple/goal (rviz "2D Nav Goal"): the robot sets off; cancelling it gives a
  // zero Twist within 0.5 s.
  // Latched: a message published at once on a fresh connection can be lost; rviz's goal tool
  // publishes on a connection made long before.
  ros::Publisher simple =
      nh.advertise<geometry_msgs::PoseStamped>("/move_base_simple/goal", 1, /*latch=*/true);
  ASSERT_TRUE(SpinSimUntil([&] { return simple.getNumSubscribers() > 0; }, 10.0));
  const double driven = watch.status->distance_driven_m;
  // Published again after 20 s without motion, as a user clicks again: on a loaded machine a
  // single goal published right after the connection was seen was, rarely, never received
  // (the navigation nodelet logged no goal). How often it took is printed.
  int publishes = 0;
  bool set_off = false;
  while (!set_off && publishes < 5) {
    simple.publish(Goal(GoalAlongTheLoop(map, T_base_camera, 5.0)).target_pose);
    ++publishes;
    set_off = SpinSimUntil([&] { return watch.status->distance_driven_m > driven + 0.3; }, 20.0);
  }
  std::printf("simple goal: the robot set off after %d publication(s)\n", publishes);
  ASSERT_TRUE(set_off) << "the robot did not set off for the simple goal (published " << publishes
                       << " times)";
  const size_t before_cancel = watch.cmds.size();
  const ros::WallTime cancelled = ros::WallTime::now();
  client.cancelAllGoals();
  auto zero_since_cancel = [&]() -> double {
    for (size_t i = before_cancel; i < watch.cmds.size(); ++i) {
      const auto& c = watch.cmds[i];
      if (c.first >= cancelled && c.second.linear.x == 0.0 && c.second.angular.z == 0.0) {
        return (c.first - cancelled).toSec();
      }
    }
    return -1.0;
  };
  ASSERT_TRUE(SpinSimUntil([&] { return zero_since_cancel() >= 0.0; }, 2.0)) << "no zero Twist";
  std::printf("zero Twist %.3f s after the cancel\n", zero_since_cancel());
  EXPECT_LE(zero_since_cancel(), 0.5);
  // And no motion command after it.
  SpinSimUntil([] { return false; }, 1.0);
  for (size_t i = before_cancel; i < watch.cmds.size(); ++i) {
    if (watch.cmds[i].first < cancelled + ros::WallDuration(zero_since_cancel())) continue;
    EXPECT_EQ(watch.cmds[i].second.linear.x, 0.0) << "moving again after the cancel";
  }
  EXPECT_EQ(watch.Collisions(), 0)
      << "after the simple goal: furniture/walls " << watch.status->static_collisions
      << ", walkers " << watch.status->pedestrian_collisions;

  // 3. A goal far off the map: ABORTED with the reason as the text.
  client.sendGoal(Goal({100.0, 100.0}));
  ASSERT_TRUE(SpinSimUntil([&] { return client.getState().isDone(); }, 30.0));
  EXPECT_EQ(client.getState(), actionlib::SimpleClientGoalState::ABORTED);
  std::printf("off-map goal: %s\n", client.getState().getText().c_str());
  EXPECT_FALSE(client.getState().getText().empty());
}

}  // namespace
}  // namespace icgm_slam::test
