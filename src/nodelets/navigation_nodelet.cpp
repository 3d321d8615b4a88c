// Navigation nodelet (thesis ch. 6.1.2 with local obstacle avoidance): a move_base-style action
// server around the core GoalSession (core/nav/goal_session.h: the map, the goal's wait for
// pose and tf, the Navigator with its Dijkstra route, eq. 6.5 pointer, OMPL detours and
// tracking controller with a safety stop).
// Inputs: the action `move_base` (move_base_msgs/MoveBaseAction) or `move_base_simple/goal`
// (forwarded to it, as move_base does), the localized pose (tf map -> base_link, from the map
// builder in localization mode), `depth` + `camera_info` (obstacles; base -> camera from tf).
// Outputs: `cmd_vel` at ~control_rate_hz while a goal is active, a zero Twist at once when it
// ends, is cancelled or preempted; feedback with the localized pose; rviz outputs
// (navigation_viz.h). A goal that cannot be followed ends ABORTED with the reason as the result
// text (no or corrupt map, goal off the map or in an obstacle, no pose or goal frame on tf for
// ~pose_wait_s, no depth for too long), never with a crash.
#include <memory>
#include <optional>
#include <string>

#include <actionlib/server/simple_action_server.h>
#include <geometry_msgs/Twist.h>
#include <move_base_msgs/MoveBaseAction.h>
#include <nodelet/nodelet.h>
#include <ros/ros.h>
#include <sensor_msgs/CameraInfo.h>
#include <sensor_msgs/Image.h>
#include <std_srvs/Trigger.h>
#include <pluginlib/class_list_macros.hpp>

#include "core/nav/goal_session.h"
#include "nodelets/navigation_tf.h"
#include "nodelets/navigation_viz.h"
#include "ros_bridge/conversions.h"
#include "ros_bridge/navigation_msgs.h"

namespace icgm_slam {

namespace rb = icgm::ros_bridge;

class NavigationNodelet : public nodelet::Nodelet {
  using Server = actionlib::SimpleActionServer<move_base_msgs::MoveBaseAction>;

 private:
  void onInit() override {
    ros::NodeHandle& nh = getNodeHandle();
    ros::NodeHandle& pnh = getPrivateNodeHandle();
    // Parameters
    std::string config_file, map_frame, odom_frame, base_frame;
    double pose_wait_s = 5.0;
    pnh.param<std::string>("config_file", config_file, "");
    pnh.param<std::string>("map_path", map_path_, "");
    pnh.param<std::string>("map_frame", map_frame, "map");
    pnh.param<std::string>("odom_frame", odom_frame, "odom");
    pnh.param<std::string>("base_frame", base_frame, "base_link");
    pnh.param<std::string>("camera_frame", camera_frame_, "camera_rgb_optical_frame");
    pnh.param("control_rate_hz", control_rate_hz_, 10.0);
    pnh.param("pose_wait_s", pose_wait_s, 5.0);
    pnh.param("depth_scale", depth_scale_, 1000.0);
    try {
      session_ = std::make_unique<icgm::GoalSession>(
          config_file.empty() ? icgm::NavigationOptions() : icgm::LoadNavigationOptions(config_file),
          pose_wait_s);
    } catch (const std::exception& e) {
      NODELET_FATAL("navigation: bad configuration: %s", e.what());
      throw;
    }
    tf_ = std::make_unique<icgm::nodelets::NavigationTf>(pnh, map_frame, odom_frame, base_frame);
    viz_ = std::make_unique<icgm::nodelets::NavigationViz>(nh, map_frame, base_frame);
    loadMap();
    // Publications
    cmd_pub_ = nh.advertise<geometry_msgs::Twist>("cmd_vel", 10);
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
    const icgm::Status s = session_->LoadMap(map_path_);
    if (s.ok()) {
      NODELET_INFO("navigation: map %s: %d keyframes", map_path_.c_str(), session_->map().size());
    } else {
      NODELET_ERROR("navigation: %s; goals are aborted until ~reload_map succeeds",
                    s.reason().c_str());
    }
    return s;
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
    if (s.ok() && tf_->FeedPose(session_.get(), &pose_error_)) {
      s = session_->UpdateDepth(rb::FromRos(msg->header.stamp), depth_m, intrinsics_, *extrinsic);
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
    const icgm::Status s = session_->Accept(ros::WallTime::now().toSec());
    if (!s.ok()) finish(false, s.reason());
  }

  void preemptCb() {
    session_->Cancel();
    cmd_pub_.publish(geometry_msgs::Twist());
    if (server_->isActive()) server_->setPreempted(move_base_msgs::MoveBaseResult(), "cancelled");
  }

  void controlCb(const ros::TimerEvent&) {
    if (!server_->isActive()) return;
    const icgm::GoalCycleInputs in =
        tf_->CycleInputs(session_.get(), goal_, camera_frame_, 1.0 / control_rate_hz_);
    const ros::Time now = rb::ToRos(in.now);
    const icgm::GoalCycle c = session_->Cycle(in);
    using R = icgm::GoalCycleResult;
    if (c.result == R::kStarted) {
      NODELET_INFO("navigation: %s", c.text.c_str());
      viz_->PublishRoute(session_->navigator(), now);
    }
    if (c.result == R::kDriving) {
      cmd_pub_.publish(rb::ToTwistMsg(c.command));
      if (in.T_map_base) server_->publishFeedback(viz_->Feedback(*in.T_map_base, now));
      viz_->PublishDebug(session_->navigator(), now);
    }
    if (c.result == R::kSucceeded || c.result == R::kAborted) {
      finish(c.result == R::kSucceeded, c.text);
    }
  }

  // Ends the active goal: a zero Twist first, then the result with the reason as its text.
  void finish(bool succeeded, const std::string& text) {
    session_->Cancel();
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
    res.message = s.ok() ? "loaded " + map_path_ + " (" +
                               std::to_string(session_->map().size()) + " keyframes)"
                         : s.reason();
    return true;
  }

  // Subscriptions
  ros::Subscriber depth_sub_, info_sub_, simple_goal_sub_;
  std::unique_ptr<Server> server_;
  std::unique_ptr<icgm::nodelets::NavigationTf> tf_;
  // Publications
  ros::Publisher cmd_pub_, simple_goal_pub_;
  std::unique_ptr<icgm::nodelets::NavigationViz> viz_;
  ros::ServiceServer reload_srv_;
  ros::Timer timer_;
  // Parameters
  std::string map_path_, camera_frame_;
  double control_rate_hz_ = 10.0, depth_scale_ = 1000.0;
  // State (callbacks run on the nodelet's single-threaded queue: no lock)
  std::unique_ptr<icgm::GoalSession> session_;
  std::string pose_error_;
  bool have_info_ = false;
  icgm::CameraIntrinsics intrinsics_;
  geometry_msgs::PoseStamped goal_;
};

}  // namespace icgm_slam

PLUGINLIB_EXPORT_CLASS(icgm_slam::NavigationNodelet, nodelet::Nodelet)
