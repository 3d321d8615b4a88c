// Navigation nodelet (thesis ch. 6.1.2): the hybrid map keeps a correct topology, so a route is
// Dijkstra's shortest path on its graph (keyframe nodes, odometry and loop-closure links). Loads
// a saved SQLite map; on each goal (e.g. rviz's "2D Nav Goal") plans from the keyframe nearest
// the robot (tf map -> base_link) to the keyframe nearest the goal and publishes the route
// (nav_msgs/Path, latched) and its markers. A missing or corrupt map is reported, not fatal:
// goals are then answered with an empty route until `~reload_map` succeeds.
#include <cstdio>
#include <memory>
#include <string>

#include <geometry_msgs/PoseStamped.h>
#include <nav_msgs/Path.h>
#include <nodelet/nodelet.h>
#include <ros/ros.h>
#include <std_srvs/Trigger.h>
#include <tf2_geometry_msgs/tf2_geometry_msgs.h>
#include <tf2_ros/buffer.h>
#include <tf2_ros/transform_listener.h>
#include <visualization_msgs/MarkerArray.h>
#include <pluginlib/class_list_macros.hpp>

#include <icgm_slam/PlanRoute.h>

#include "core/common/status.h"
#include "core/map/map_store.h"
#include "core/nav/graph_planner.h"
#include "ros_bridge/conversions.h"
#include "ros_bridge/route_msgs.h"

namespace icgm_slam {

class NavigationNodelet : public nodelet::Nodelet {
 private:
  void onInit() override {
    ros::NodeHandle& nh = getNodeHandle();
    ros::NodeHandle& pnh = getPrivateNodeHandle();
    // Parameters
    pnh.param<std::string>("map_path", map_path_, "");
    pnh.param<std::string>("map_frame", map_frame_, "map");
    pnh.param<std::string>("base_frame", base_frame_, "base_link");
    pnh.param("goal_tolerance_m", goal_tolerance_m_, 2.0);
    pnh.param("tf_timeout_s", tf_timeout_s_, 0.2);
    tf_listener_ = std::make_unique<tf2_ros::TransformListener>(tf_buffer_);
    loadMap();
    // Publications (latched: rviz started later still shows the last route)
    route_pub_ = nh.advertise<nav_msgs::Path>("route", 1, true);
    markers_pub_ = nh.advertise<visualization_msgs::MarkerArray>("route/markers", 1, true);
    reload_srv_ = pnh.advertiseService("reload_map", &NavigationNodelet::reloadCb, this);
    plan_srv_ = pnh.advertiseService("plan", &NavigationNodelet::planCb, this);
    goal_sub_ = nh.subscribe("goal", 1, &NavigationNodelet::goalCb, this);
  }

  icgm::Status loadMap() {
    planner_.reset();
    map_error_.clear();
    try {
      if (map_path_.empty()) throw icgm::LoadError("no map: ~map_path is not set");
      const icgm::HybridMap map = icgm::LoadMap(map_path_);
      if (map.empty()) throw icgm::LoadError("map '" + map_path_ + "' has no keyframes");
      planner_ = std::make_unique<icgm::GraphPlanner>(icgm::GraphPlanner::FromMap(map));
      NODELET_INFO("navigation: map %s: %d keyframes, %zu links", map_path_.c_str(), map.size(),
                   map.links().size());
      return icgm::Status::Ok();
    } catch (const std::exception& e) {
      map_error_ = e.what();
      NODELET_ERROR(
          "navigation: cannot load the map: %s; goals get an empty route until "
          "~reload_map succeeds",
          map_error_.c_str());
      return icgm::Status::Error(map_error_);
    }
  }

  icgm::Status robotPosition(icgm::Vec3* position) {
    try {
      const auto t = tf_buffer_.lookupTransform(map_frame_, base_frame_, ros::Time(0),
                                                ros::Duration(tf_timeout_s_));
      *position = icgm::ros_bridge::FromTransformMsg(t.transform).translation();
      return icgm::Status::Ok();
    } catch (const tf2::TransformException& e) {
      return icgm::Status::Error("no robot pose (tf " + map_frame_ + " -> " + base_frame_ +
                                 "): " + e.what());
    }
  }

  // Plans between the keyframes nearest `start` and `goal` (map frame). Both must lie within
  // goal_tolerance_m (horizontally) of a keyframe: elsewhere the map knows no way.
  icgm::Status plan(const icgm::Vec3& start, const icgm::Vec3& goal, icgm::Route* route) const {
    if (!planner_) return icgm::Status::Error("no map loaded (" + map_error_ + ")");
    const int from = planner_->NearestNode(start);
    const int to = planner_->NearestNode(goal);
    if (icgm::Status s = checkNear("start", from, start); !s.ok()) return s;
    if (icgm::Status s = checkNear("goal", to, goal); !s.ok()) return s;
    return planner_->PlanRoute(from, to, route);
  }

  icgm::Status checkNear(const char* what, int node, const icgm::Vec3& p) const {
    const double d = (planner_->position(node) - p).head<2>().norm();
    if (goal_tolerance_m_ <= 0 || d <= goal_tolerance_m_) return icgm::Status::Ok();
    char buf[256];
    std::snprintf(buf, sizeof(buf),
                  "%s (%.2f, %.2f) is %.2f m from the nearest keyframe %d (goal_tolerance_m %.2f)",
                  what, p.x(), p.y(), d, node, goal_tolerance_m_);
    return icgm::Status::Error(buf);
  }

  void publish(const icgm::Route& route) {
    const icgm::Time now = icgm::ros_bridge::FromRos(ros::Time::now());
    const icgm::GraphPlanner empty;
    const icgm::GraphPlanner& graph = planner_ ? *planner_ : empty;
    route_pub_.publish(icgm::ros_bridge::ToRoutePath(graph, route, map_frame_, now));
    markers_pub_.publish(icgm::ros_bridge::ToRouteMarkers(graph, route, map_frame_, now));
  }

  void goalCb(const geometry_msgs::PoseStamped::ConstPtr& msg) {
    icgm::Route route;
    geometry_msgs::PoseStamped goal = *msg;
    icgm::Vec3 start;
    icgm::Status s = icgm::Status::Ok();
    if (!goal.header.frame_id.empty() && goal.header.frame_id != map_frame_) {
      try {
        goal = tf_buffer_.transform(*msg, map_frame_, ros::Duration(tf_timeout_s_));
      } catch (const tf2::TransformException& e) {
        s = icgm::Status::Error("goal frame '" + msg->header.frame_id + "' not on tf: " + e.what());
      }
    }
    if (s.ok()) s = robotPosition(&start);
    if (s.ok()) s = plan(start, icgm::ros_bridge::FromPointMsg(goal.pose.position), &route);
    if (s.ok()) {
      NODELET_INFO("navigation: route of %.2f m over %zu keyframes (%d -> %d)", route.length_m,
                   route.nodes.size(), route.nodes.front(), route.nodes.back());
    } else {
      route = icgm::Route();
      if (planner_) {
        NODELET_WARN("navigation: no route: %s", s.reason().c_str());
      } else {
        NODELET_ERROR("navigation: no route: %s", s.reason().c_str());
      }
    }
    publish(route);
  }

  bool planCb(icgm_slam::PlanRoute::Request& req, icgm_slam::PlanRoute::Response& res) {
    icgm::Vec3 start = icgm::ros_bridge::FromPointMsg(req.start);
    icgm::Route route;
    icgm::Status s = req.start_from_robot ? robotPosition(&start) : icgm::Status::Ok();
    if (s.ok()) s = plan(start, icgm::ros_bridge::FromPointMsg(req.goal), &route);
    res.success = s.ok();
    if (!s.ok()) {
      res.message = s.reason();
      return true;
    }
    res.path = icgm::ros_bridge::ToRoutePath(*planner_, route, map_frame_,
                                             icgm::ros_bridge::FromRos(ros::Time::now()));
    res.keyframe_ids.assign(route.nodes.begin(), route.nodes.end());
    res.length_m = route.length_m;
    res.message = "route of " + std::to_string(route.length_m) + " m over " +
                  std::to_string(route.nodes.size()) + " keyframes";
    return true;
  }

  bool reloadCb(std_srvs::Trigger::Request&, std_srvs::Trigger::Response& res) {
    getPrivateNodeHandle().param<std::string>("map_path", map_path_, map_path_);
    const icgm::Status s = loadMap();
    res.success = s.ok();
    res.message =
        s.ok() ? "loaded " + map_path_ + " (" + std::to_string(planner_->size()) + " keyframes)"
               : s.reason();
    return true;
  }

  // Callbacks run on the nodelet's single-threaded queue, so the state needs no lock.
  tf2_ros::Buffer tf_buffer_;
  std::unique_ptr<tf2_ros::TransformListener> tf_listener_;
  ros::Subscriber goal_sub_;
  ros::Publisher route_pub_, markers_pub_;
  ros::ServiceServer reload_srv_, plan_srv_;
  // Parameters
  std::string map_path_, map_frame_, base_frame_;
  double goal_tolerance_m_ = 2.0;
  double tf_timeout_s_ = 0.2;
  // State
  std::unique_ptr<icgm::GraphPlanner> planner_;
  std::string map_error_;
};

}  // namespace icgm_slam

PLUGINLIB_EXPORT_CLASS(icgm_slam::NavigationNodelet, nodelet::Nodelet)
