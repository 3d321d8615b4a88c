// Navigation nodelet (thesis ch. 6.1.2 with local obstacle avoidance): a move_base-style action
// server around the core GoalSession (core/nav/goal_session.h: the map, the goal's wait for
// pose and tf, the Navigator with its Dijkstra route, eq. 6.5 pointer, OMPL detours and
// tracking controller with a safety stop).
// Inputs: the action `move_base` (move_base_msgs/MoveBaseAction) or `move_base_simple/goal`
// (move_base_server.h), the localized pose (tf map -> base_link, from the map builder in
// localization mode), `depth` + `camera_info` (obstacles; base -> camera from tf;
// navigation_depth.h) and, from a planar scanner when there is one, `scan`
// (sensor_msgs/LaserScan; base -> its frame from tf): each scan joins the next depth image's
// obstacles (Navigator::UpdateScan; navigator.scan_tracker_only: the walker tracker only).
// Outputs: `cmd_vel` at ~control_rate_hz while a goal is active, a zero Twist at once when it
// ends, is cancelled or preempted; feedback with the localized pose; rviz outputs
// (navigation_viz.h); what the robot is doing (following, stopped and why, avoiding, rejoining,
// yielding) in the log as it changes (core/nav/navigation_phase.h). A goal that cannot be
// followed ends ABORTED with the reason as the result text (no or corrupt map, goal off the map
// or in an obstacle, no pose or goal frame on tf for ~pose_wait_s, no depth for too long), never
// with a crash.
#include <memory>
#include <string>

#include <nodelet/nodelet.h>
#include <ros/ros.h>
#include <sensor_msgs/CameraInfo.h>
#include <sensor_msgs/Image.h>
#include <sensor_msgs/LaserScan.h>
#include <std_srvs/Trigger.h>
#include <pluginlib/class_list_macros.hpp>

#include "core/nav/goal_session.h"
#include "core/nav/navigation_phase.h"
#include "nodelets/move_base_server.h"
#include "nodelets/navigation_depth.h"
#include "nodelets/navigation_tf.h"
#include "nodelets/navigation_viz.h"
#include "nodelets/nodelet_params.h"
#include "ros_bridge/conversions.h"
#include "ros_bridge/navigation_msgs.h"

namespace icgm_slam {

namespace nl = icgm::nodelets;

class NavigationNodelet : public nodelet::Nodelet {
 private:
  void onInit() override {
    ros::NodeHandle& nh = getNodeHandle();
    ros::NodeHandle& pnh = getPrivateNodeHandle();
    // Parameters
    const nl::FrameNames frames = nl::ReadFrameNames(pnh);
    const std::string config_file = nl::Param(pnh, "config_file", "");
    map_path_ = nl::Param(pnh, "map_path", "");
    camera_frame_ = nl::Param(pnh, "camera_frame", "camera_rgb_optical_frame");
    control_rate_hz_ = nl::Param(pnh, "control_rate_hz", 10.0);
    nl::LoadConfiguration("navigation", [&] {
      if (!(control_rate_hz_ > 0.0 && control_rate_hz_ <= 1000.0)) {
        throw icgm::LoadError("~control_rate_hz " + std::to_string(control_rate_hz_) +
                              " not in (0, 1000]");
      }
      icgm::NavigationOptions options;
      if (!config_file.empty()) options = icgm::LoadNavigationOptions(config_file);
      session_ = std::make_unique<icgm::GoalSession>(options, nl::Param(pnh, "pose_wait_s", 5.0));
    });
    tf_ = std::make_unique<nl::NavigationTf>(pnh, frames.map, frames.odom, frames.base);
    depth_ = std::make_unique<nl::NavigationDepth>(nh, pnh);
    loadMap();
    // Publications (cmd_vel and the action: move_base_server.h)
    viz_ = std::make_unique<nl::NavigationViz>(nh, frames.map, frames.base);
    reload_srv_ = pnh.advertiseService("reload_map", &NavigationNodelet::reloadCb, this);
    // Subscriptions
    depth_sub_ = nh.subscribe("depth", 2, &NavigationNodelet::depthCb, this);
    info_sub_ = nh.subscribe("camera_info", 2, &NavigationNodelet::infoCb, this);
    scan_sub_ = nh.subscribe("scan", 2, &NavigationNodelet::scanCb, this);
    server_ = std::make_unique<nl::MoveBaseServer>(
        nh, [this](const geometry_msgs::PoseStamped& target) { return goalCb(target); },
        [this] { session_->Cancel(); });
    timer_ =
        nh.createTimer(ros::Duration(1.0 / control_rate_hz_), &NavigationNodelet::controlCb, this);
    icgm::nodelets::WarnUnknownParams(getPrivateNodeHandle(), "navigation");
  }

  icgm::Status loadMap() {
    const icgm::Status s = session_->LoadMap(map_path_);
    if (s.ok()) {
      NODELET_INFO("navigation: map %s: %d keyframes", map_path_.c_str(), session_->map().size());
      if (!session_->map_note().empty()) {
        NODELET_WARN("navigation: %s", session_->map_note().c_str());
      }
    } else {
      NODELET_ERROR("navigation: %s; goals are aborted until ~reload_map succeeds",
                    s.reason().c_str());
    }
    return s;
  }

  void infoCb(const sensor_msgs::CameraInfo::ConstPtr& msg) { depth_->SetInfo(*msg); }

  void depthCb(const sensor_msgs::Image::ConstPtr& msg) {
    bool wrong_size = false;
    const icgm::Status s = depth_->Feed(*msg, tf_.get(), session_.get(), &wrong_size);
    if (wrong_size) {
      NODELET_ERROR_THROTTLE(5, "navigation: depth refused: %s", s.reason().c_str());
    } else if (!s.ok()) {
      NODELET_WARN_THROTTLE(5, "navigation: depth not used: %s", s.reason().c_str());
    }
  }

  void scanCb(const sensor_msgs::LaserScan::ConstPtr& msg) {
    const std::optional<icgm::Pose3> extrinsic = tf_->ScannerExtrinsic(msg->header.frame_id);
    if (!extrinsic) return;  // waiting for base -> scanner (the source logs it)
    session_->UpdateScan(icgm::ros_bridge::FromLaserScanMsg(*msg), *extrinsic);
  }

  // A new goal (preempting any active one) starts at the next control cycle.
  icgm::Status goalCb(const geometry_msgs::PoseStamped& target) {
    goal_ = target;
    return session_->Accept(ros::WallTime::now().toSec());
  }

  void controlCb(const ros::TimerEvent&) {
    if (!server_->active()) return;
    const icgm::GoalCycleInputs in =
        tf_->CycleInputs(session_.get(), goal_, camera_frame_, 1.0 / control_rate_hz_);
    const ros::Time now = icgm::ros_bridge::ToRos(in.now);
    const icgm::GoalCycle c = session_->Cycle(in);
    using R = icgm::GoalCycleResult;
    if (c.result == R::kStarted) {
      NODELET_INFO("navigation: %s", c.text.c_str());
      phase_log_.Reset();
      viz_->PublishRoute(session_->navigator(), now);
    }
    if (c.result == R::kDriving) {
      const auto feedback =
          in.T_map_base ? viz_->Feedback(*in.T_map_base, now) : move_base_msgs::MoveBaseFeedback();
      server_->Drive(c.command, in.T_map_base ? &feedback : nullptr);
      viz_->PublishDebug(session_->navigator(), now);
      if (const auto line = phase_log_.Update(now.toSec(), session_->navigator().status())) {
        NODELET_INFO("navigation: %s", line->c_str());
      }
    }
    if (c.result == R::kSucceeded || c.result == R::kAborted) {
      finish(c.result == R::kSucceeded, c.text);
    }
  }

  // Ends the active goal: a zero Twist first, then the result with the reason as its text.
  void finish(bool succeeded, const std::string& text) {
    session_->Cancel();
    server_->Finish(succeeded, text);
  }

  bool reloadCb(std_srvs::Trigger::Request&, std_srvs::Trigger::Response& res) {
    finish(false, "the map is being reloaded");
    nl::ParamInto(getPrivateNodeHandle(), "map_path", &map_path_);
    const icgm::Status s = loadMap();
    res.success = s.ok();
    res.message = s.ok() ? "loaded " + map_path_ + " (" + std::to_string(session_->map().size()) +
                               " keyframes)"
                         : s.reason();
    return true;
  }

  // Subscriptions
  ros::Subscriber depth_sub_, info_sub_, scan_sub_;
  std::unique_ptr<nl::MoveBaseServer> server_;  // the action, move_base_simple/goal, cmd_vel
  std::unique_ptr<nl::NavigationTf> tf_;
  std::unique_ptr<nl::NavigationDepth> depth_;
  // Publications
  std::unique_ptr<nl::NavigationViz> viz_;
  ros::ServiceServer reload_srv_;
  ros::Timer timer_;
  icgm::PhaseLog phase_log_;  // what the robot is doing, logged as it changes
  // Parameters
  std::string map_path_, camera_frame_;
  double control_rate_hz_ = 10.0;
  // State (callbacks run on the nodelet's single-threaded queue: no lock)
  std::unique_ptr<icgm::GoalSession> session_;
  geometry_msgs::PoseStamped goal_;
};

}  // namespace icgm_slam

PLUGINLIB_EXPORT_CLASS(icgm_slam::NavigationNodelet, nodelet::Nodelet)
