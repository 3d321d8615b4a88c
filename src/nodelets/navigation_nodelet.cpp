// Navigation nodelet (thesis ch. 6.1.2 with local obstacle avoidance): a move_base-style action
// server that drives the robot to goals on a learned map with the core Navigator
// (core/nav/navigator.h: Dijkstra route on the map graph, eq. 6.5 pointer, OMPL detours around
// obstacles seen in the depth, tracking controller with a safety stop).
// Inputs: the action `move_base` (move_base_msgs/MoveBaseAction) or `move_base_simple/goal`
// (forwarded to it, as move_base does), the localized pose (tf map -> base_link, from the map
// builder in localization mode), `depth` + `camera_info` (obstacles; base -> camera from tf).
// Outputs: `cmd_vel` at ~control_rate_hz while a goal is active, a zero Twist at once when it
// ends, is cancelled or preempted; feedback with the localized pose; for rviz `route`,
// `local_plan` (nav_msgs/Path), `obstacle_grid` (nav_msgs/OccupancyGrid) and `footprint`
// (geometry_msgs/PolygonStamped). A goal that cannot be followed ends ABORTED with the reason
// as the result text (no or corrupt map, goal off the map or in an obstacle, no pose or goal
// frame on tf for ~pose_wait_s, no depth for too long), never with a crash.
#include <memory>
#include <optional>
#include <string>

#include <actionlib/server/simple_action_server.h>
#include <geometry_msgs/PolygonStamped.h>
#include <geometry_msgs/Twist.h>
#include <move_base_msgs/MoveBaseAction.h>
#include <nav_msgs/OccupancyGrid.h>
#include <nav_msgs/Path.h>
#include <nodelet/nodelet.h>
#include <ros/ros.h>
#include <sensor_msgs/CameraInfo.h>
#include <sensor_msgs/Image.h>
#include <std_srvs/Trigger.h>
#include <pluginlib/class_list_macros.hpp>

#include "core/map/map_store.h"
#include "core/nav/navigation_options.h"
#include "core/nav/navigator.h"
#include "nodelets/navigation_tf.h"
#include "ros_bridge/conversions.h"
#include "ros_bridge/navigation_msgs.h"
#include "ros_bridge/map_product_msgs.h"

namespace icgm_slam {

namespace rb = icgm::ros_bridge;

class NavigationNodelet : public nodelet::Nodelet {
  using Server = actionlib::SimpleActionServer<move_base_msgs::MoveBaseAction>;

 private:
  void onInit() override {
    ros::NodeHandle& nh = getNodeHandle();
    ros::NodeHandle& pnh = getPrivateNodeHandle();
    // Parameters
    std::string config_file, map_frame, odom_frame;
    pnh.param<std::string>("config_file", config_file, "");
    pnh.param<std::string>("map_path", map_path_, "");
    pnh.param<std::string>("map_frame", map_frame_, "map");
    pnh.param<std::string>("odom_frame", odom_frame, "odom");
    pnh.param<std::string>("base_frame", base_frame_, "base_link");
    pnh.param<std::string>("camera_frame", camera_frame_, "camera_rgb_optical_frame");
    pnh.param("control_rate_hz", control_rate_hz_, 10.0);
    pnh.param("pose_wait_s", pose_wait_s_, 5.0);
    pnh.param("depth_scale", depth_scale_, 1000.0);
    try {
      if (!config_file.empty()) options_ = icgm::LoadNavigationOptions(config_file);
    } catch (const std::exception& e) {
      NODELET_FATAL("navigation: bad configuration: %s", e.what());
      throw;
    }
    navigator_ = std::make_unique<icgm::Navigator>(options_);
    tf_ = std::make_unique<icgm::nodelets::NavigationTf>(pnh, map_frame_, odom_frame, base_frame_);
    loadMap();
    // Publications (the route latched: rviz started later still shows it)
    cmd_pub_ = nh.advertise<geometry_msgs::Twist>("cmd_vel", 10);
    route_pub_ = nh.advertise<nav_msgs::Path>("route", 1, true);
    local_plan_pub_ = nh.advertise<nav_msgs::Path>("local_plan", 1);
    grid_pub_ = nh.advertise<nav_msgs::OccupancyGrid>("obstacle_grid", 1);
    footprint_pub_ = nh.advertise<geometry_msgs::PolygonStamped>("footprint", 1);
    simple_goal_pub_ = nh.advertise<move_base_msgs::MoveBaseActionGoal>("move_base/goal", 1);
    reload_srv_ = pnh.advertiseService("reload_map", &NavigationNodelet::reloadCb, this);
    // Subscriptions
    depth_sub_ = nh.subscribe("depth", 2, &NavigationNodelet::depthCb, this);
    info_sub_ = nh.subscribe("camera_info", 2, &NavigationNodelet::infoCb, this);
    simple_goal_sub_ =
        nh.subscribe("move_base_simple/goal", 1, &NavigationNodelet::simpleGoalCb, this);
    server_ = std::make_unique<Server>(nh, "move_base", false);
    server_->registerGoalCallback([this] { goalCb(); });
    server_->registerPreemptCallback([this] { preemptCb(); });
    server_->start();
    timer_ =
        nh.createTimer(ros::Duration(1.0 / control_rate_hz_), &NavigationNodelet::controlCb, this);
  }

  icgm::Status loadMap() {
    map_error_.clear();
    map_set_ = false;
    try {
      if (map_path_.empty()) throw icgm::LoadError("~map_path is not set");
      map_ = icgm::LoadMap(map_path_);
      if (map_.empty()) throw icgm::LoadError("map '" + map_path_ + "' has no keyframes");
      NODELET_INFO("navigation: map %s: %d keyframes", map_path_.c_str(), map_.size());
      return icgm::Status::Ok();
    } catch (const std::exception& e) {
      map_error_ = std::string("no map: ") + e.what();
      NODELET_ERROR("navigation: %s; goals are aborted until ~reload_map succeeds",
                    map_error_.c_str());
      return icgm::Status::Error(map_error_);
    }
  }

  // Hands the localized base to the navigator; false (reason in pose_error_) when not on tf.
  std::optional<icgm::Pose3> updatePose() {
    icgm::Pose3 pose;
    icgm::Time stamp;
    bool fix = false;
    const icgm::Status s = tf_->LocalizedBase(&pose, &stamp, &fix);
    if (!s.ok()) {
      pose_error_ = s.reason();
      return std::nullopt;
    }
    navigator_->UpdatePose(stamp, pose, fix);
    return pose;
  }

  void infoCb(const sensor_msgs::CameraInfo::ConstPtr& msg) {
    have_info_ = rb::FromCameraInfo(*msg, depth_scale_, &intrinsics_).ok();
  }

  void depthCb(const sensor_msgs::Image::ConstPtr& msg) {
    const std::optional<icgm::Pose3> extrinsic = tf_->Extrinsic(msg->header.frame_id);
    cv::Mat depth_m;
    icgm::Status s = extrinsic ? icgm::Status::Ok() : icgm::Status::Error("no base -> camera");
    if (s.ok() && !have_info_) s = icgm::Status::Error("no valid camera_info");
    if (s.ok()) s = rb::DepthFromImageMsg(*msg, depth_scale_, &depth_m);
    if (s.ok() && updatePose()) {
      s = navigator_->UpdateDepth(rb::FromRos(msg->header.stamp), depth_m, intrinsics_, *extrinsic);
    }
    if (!s.ok()) NODELET_WARN_THROTTLE(5, "navigation: depth not used: %s", s.reason().c_str());
  }

  void simpleGoalCb(const geometry_msgs::PoseStamped::ConstPtr& msg) {
    move_base_msgs::MoveBaseActionGoal goal;
    goal.header.stamp = ros::Time::now();
    goal.goal.target_pose = *msg;
    simple_goal_pub_.publish(goal);
  }

  // A new goal (preempting any active one) starts at the next control cycle.
  void goalCb() {
    goal_ = server_->acceptNewGoal()->target_pose;
    goal_received_ = ros::WallTime::now();
    pending_ = true;
    navigator_->Cancel();
    if (!map_error_.empty()) finish(false, map_error_);
  }

  void preemptCb() {
    pending_ = false;
    navigator_->Cancel();
    cmd_pub_.publish(geometry_msgs::Twist());
    if (server_->isActive()) server_->setPreempted(move_base_msgs::MoveBaseResult(), "cancelled");
  }

  // Starts the pending goal once the pose, the extrinsic and the goal's frame are on tf; gives
  // up after ~pose_wait_s.
  void startGoal(const std::optional<icgm::Pose3>& pose) {
    const std::optional<icgm::Pose3> extrinsic = tf_->Extrinsic(camera_frame_);
    Eigen::Vector2d goal;
    icgm::Status s = pose ? tf_->GoalInMap(goal_, &goal) : icgm::Status::Error(pose_error_);
    if (s.ok() && !extrinsic) {
      s = icgm::Status::Error("no extrinsic (tf " + base_frame_ + " -> " + camera_frame_ + ")");
    }
    if (!s.ok()) {
      if ((ros::WallTime::now() - goal_received_).toSec() > pose_wait_s_) finish(false, s.reason());
      return;
    }
    pending_ = false;
    if (!map_set_) s = navigator_->SetMap(map_, *extrinsic);
    map_set_ = s.ok();
    if (s.ok()) s = navigator_->SetGoal(goal, *pose);
    if (!s.ok()) return finish(false, s.reason());
    NODELET_INFO("navigation: goal (%.2f, %.2f): route of %zu nodes", goal.x(), goal.y(),
                 navigator_->route_nodes().size());
    route_pub_.publish(
        rb::ToPlanarPathMsg(navigator_->route(), map_frame_, rb::FromRos(ros::Time::now())));
  }

  void controlCb(const ros::TimerEvent&) {
    if (!server_->isActive()) return;
    const std::optional<icgm::Pose3> pose = updatePose();
    if (pending_) return startGoal(pose);
    const ros::Time now = ros::Time::now();
    const icgm::NavigationStatus s = navigator_->Update(rb::FromRos(now), 1.0 / control_rate_hz_);
    cmd_pub_.publish(rb::ToTwistMsg(s.command));
    if (pose) {
      move_base_msgs::MoveBaseFeedback feedback;
      feedback.base_position.header.frame_id = map_frame_;
      feedback.base_position.header.stamp = now;
      feedback.base_position.pose = rb::ToPoseMsg(*pose);
      server_->publishFeedback(feedback);
    }
    publishViz(now);
    if (s.state == icgm::NavigationState::kReached) {
      finish(true, "reached: " + std::to_string(s.distance_to_goal_m) + " m from the goal");
    } else if (s.state == icgm::NavigationState::kAborted) {
      finish(false, s.reason);
    }
  }

  // Debug outputs, built only while someone listens (the grid at most twice a second).
  void publishViz(const ros::Time& now) {
    const icgm::Time t = rb::FromRos(now);
    if (local_plan_pub_.getNumSubscribers() > 0) {
      local_plan_pub_.publish(rb::ToPlanarPathMsg(navigator_->local_path(), map_frame_, t));
    }
    if (footprint_pub_.getNumSubscribers() > 0) {
      footprint_pub_.publish(rb::ToPolygonMsg(
          rb::CircleFootprint(options_.navigator.robot_radius_m, 24), base_frame_, t));
    }
    if (grid_pub_.getNumSubscribers() > 0 && (now - last_grid_).toSec() >= 0.5) {
      grid_pub_.publish(rb::ToOccupancyGridMsg(navigator_->obstacles().Export(), map_frame_, t));
      last_grid_ = now;
    }
  }

  // Ends the active goal: a zero Twist first, then the result with the reason as its text.
  void finish(bool succeeded, const std::string& text) {
    pending_ = false;
    navigator_->Cancel();
    cmd_pub_.publish(geometry_msgs::Twist());
    if (!server_->isActive()) return;
    if (succeeded) {
      NODELET_INFO("navigation: goal succeeded (%s)", text.c_str());
      server_->setSucceeded(move_base_msgs::MoveBaseResult(), text);
    } else {
      NODELET_WARN("navigation: goal aborted: %s", text.c_str());
      server_->setAborted(move_base_msgs::MoveBaseResult(), text);
    }
  }

  bool reloadCb(std_srvs::Trigger::Request&, std_srvs::Trigger::Response& res) {
    finish(false, "the map is being reloaded");
    getPrivateNodeHandle().param<std::string>("map_path", map_path_, map_path_);
    const icgm::Status s = loadMap();
    res.success = s.ok();
    res.message = s.ok()
                      ? "loaded " + map_path_ + " (" + std::to_string(map_.size()) + " keyframes)"
                      : s.reason();
    return true;
  }

  // Subscriptions
  ros::Subscriber depth_sub_, info_sub_, simple_goal_sub_;
  std::unique_ptr<Server> server_;
  std::unique_ptr<icgm::nodelets::NavigationTf> tf_;
  // Publications
  ros::Publisher cmd_pub_, route_pub_, local_plan_pub_, grid_pub_, footprint_pub_;
  ros::Publisher simple_goal_pub_;
  ros::ServiceServer reload_srv_;
  ros::Timer timer_;
  // Parameters
  std::string map_path_, map_frame_, base_frame_, camera_frame_;
  double control_rate_hz_ = 10.0, pose_wait_s_ = 5.0, depth_scale_ = 1000.0;
  icgm::NavigationOptions options_;
  // State (callbacks run on the nodelet's single-threaded queue: no lock)
  std::unique_ptr<icgm::Navigator> navigator_;
  icgm::HybridMap map_;
  std::string map_error_, pose_error_;
  bool map_set_ = false, pending_ = false, have_info_ = false;
  icgm::CameraIntrinsics intrinsics_;
  geometry_msgs::PoseStamped goal_;
  ros::WallTime goal_received_;
  ros::Time last_grid_;
};

}  // namespace icgm_slam

PLUGINLIB_EXPORT_CLASS(icgm_slam::NavigationNodelet, nodelet::Nodelet)
