// Simulator nodelet: drives the closed-loop simulator (core/sim/closed_loop_simulator.h) with
// velocity commands (cmd_vel, geometry_msgs/Twist) and publishes what the robot's sensors give,
// under the names the pipeline and the recorded bags use (ros_bridge/topics.h): colour, depth and
// camera_info at the scenario's frame rate, wheel odometry (/odom, tf odom -> base_link) and
// /clock every step, the base -> camera extrinsic on /tf_static (latched). Ground truth for
// evaluation: the camera pose (/ground_truth/pose), the dynamic mask (only while subscribed), the
// walkers (/ground_truth/people) and the collision status (sim/status). ~num_pedestrians
// (>= 0) replaces the scenario's number of walkers. ~scanner (bool, default: the scenario's
// scanner.enabled) turns the planar scanner on: /scan (sensor_msgs/LaserScan) with every frame,
// base -> ~scanner_frame on /tf_static.
// Time is the simulator's: run the other nodes with /use_sim_time. The simulation advances by
// ~step_s every ~step_s / ~rate_factor of wall time; a command older than ~cmd_timeout_s of
// simulated time is replaced by a stop. With ~sync_topic (nav_msgs/Odometry, e.g. the fused
// odometry) the world waits, at most ~sync_timeout_s of wall time per frame, until the pipeline
// has answered the frame ~sync_lag_frames before the next one: a loaded machine slows the
// simulation down instead of making the pipeline drop frames.
#include <algorithm>
#include <cmath>
#include <deque>
#include <memory>
#include <optional>
#include <string>

#include <geometry_msgs/Twist.h>
#include <nav_msgs/Odometry.h>
#include <nodelet/nodelet.h>
#include <ros/ros.h>
#include <pluginlib/class_list_macros.hpp>

#include "core/sim/closed_loop_simulator.h"
#include "nodelets/nodelet_params.h"
#include "nodelets/sim_publishers.h"
#include "ros_bridge/conversions.h"
#include "ros_bridge/navigation_msgs.h"
#include "ros_bridge/topics.h"

namespace icgm_slam {

namespace topics = icgm::ros_bridge::topics;

class SimulatorNodelet : public nodelet::Nodelet {
 private:
  void onInit() override {
    ros::NodeHandle& nh = getNodeHandle();
    ros::NodeHandle& pnh = getPrivateNodeHandle();
    // Parameters
    namespace nodelets = icgm::nodelets;
    const std::string scenario = nodelets::Param(pnh, "scenario", "");
    const int num_pedestrians = nodelets::Param(pnh, "num_pedestrians", -1);  // < 0: scenario's
    rate_factor_ = nodelets::Param(pnh, "rate_factor", 1.0);
    step_s_ = nodelets::Param(pnh, "step_s", 0.05);
    cmd_timeout_s_ = nodelets::Param(pnh, "cmd_timeout_s", 0.5);
    const std::string depth_encoding = nodelets::Param(pnh, "depth_encoding", "16UC1");
    const std::string sync_topic = nodelets::Param(pnh, "sync_topic", "");
    sync_lag_frames_ = nodelets::Param(pnh, "sync_lag_frames", 2);
    sync_timeout_s_ = nodelets::Param(pnh, "sync_timeout_s", 2.0);
    const std::string world_frame = nodelets::Param(pnh, "world_frame", topics::kWorldFrame);
    const std::string odom_frame = nodelets::Param(pnh, "odom_frame", topics::kOdomFrame);
    const std::string base_frame = nodelets::Param(pnh, "base_frame", topics::kBaseFrame);
    const std::string camera_frame = nodelets::Param(pnh, "camera_frame", topics::kCameraFrame);
    const std::string scanner_frame = nodelets::Param(pnh, "scanner_frame", topics::kScannerFrame);
    try {
      if (scenario.empty()) throw icgm::LoadError("~scenario (a sim YAML) is not set");
      if (!(rate_factor_ > 0) || !(step_s_ > 0) || !(cmd_timeout_s_ > 0)) {
        throw icgm::LoadError("~rate_factor, ~step_s and ~cmd_timeout_s must be positive");
      }
      if (depth_encoding != "16UC1" && depth_encoding != "32FC1") {
        throw icgm::LoadError("~depth_encoding must be 16UC1 or 32FC1");
      }
      icgm::sim::SimOptions options = icgm::sim::LoadSimOptions(scenario);
      if (num_pedestrians >= 0) options.crowd.num_pedestrians = num_pedestrians;
      options.scanner.enabled = nodelets::Param(pnh, "scanner", options.scanner.enabled);
      sim_ = std::make_unique<icgm::sim::ClosedLoopSimulator>(options);
    } catch (const std::exception& e) {
      NODELET_FATAL("simulator: cannot start: %s", e.what());
      return;
    }
    // One frame every steps_per_frame_ steps: the step is shortened to divide the frame period.
    steps_per_frame_ =
        std::max(1, static_cast<int>(std::lround(1.0 / (sim_->options().frame_rate_hz * step_s_))));
    step_s_ = 1.0 / (sim_->options().frame_rate_hz * steps_per_frame_);
    // Publications
    out_ = std::make_unique<nodelets::SimPublishers>(
        nh, nodelets::SimFrames{world_frame, odom_frame, base_frame, camera_frame, scanner_frame},
        depth_encoding);
    if (sim_->options().scanner.enabled) out_->AdvertiseScan(nh);
    // Subscriptions
    cmd_sub_ = nh.subscribe("cmd_vel", 10, &SimulatorNodelet::cmdCb, this);
    if (!sync_topic.empty()) {
      sync_sub_ = nh.subscribe<nav_msgs::Odometry>(
          sync_topic, 50, [this](const nav_msgs::Odometry::ConstPtr& m) {
            answered_ = std::max(answered_, icgm::ros_bridge::FromRos(m->header.stamp));
          });
    }

    out_->PublishExtrinsic(*sim_);
    out_->PublishStep(*sim_);
    publishFrame();
    timer_ = nh.createWallTimer(ros::WallDuration(step_s_ / rate_factor_),
                                &SimulatorNodelet::stepCb, this);
    NODELET_INFO(
        "simulator: %s, %zu walkers, frames at %.1f Hz, steps of %.3f s at %.2fx real time",
        scenario.c_str(), sim_->num_pedestrians(), sim_->options().frame_rate_hz, step_s_,
        rate_factor_);
    icgm::nodelets::WarnUnknownParams(getPrivateNodeHandle(), "simulator");
  }

  void cmdCb(const geometry_msgs::Twist::ConstPtr& msg) {
    cmd_ = icgm::ros_bridge::FromTwistMsg(*msg);
    cmd_stamp_ = sim_ ? sim_->stamp() : icgm::Time();
    have_cmd_ = std::isfinite(cmd_.linear_mps) && std::isfinite(cmd_.angular_radps);
    if (!have_cmd_) NODELET_WARN_THROTTLE(5, "simulator: non-finite cmd_vel ignored (stop)");
  }

  // Holds the step that renders the next frame until the frame sync_lag_frames back is answered.
  bool waitForPipeline() {
    const bool renders = (sim_->num_steps() + 1) % steps_per_frame_ == 0;
    if (!sync_sub_ || !renders || frame_stamps_.size() < static_cast<size_t>(sync_lag_frames_)) {
      return false;
    }
    const icgm::Time needed = frame_stamps_[frame_stamps_.size() - sync_lag_frames_];
    const ros::WallTime now = ros::WallTime::now();
    if (answered_ >= needed) {
      wait_start_.reset();
      return false;
    }
    if (!wait_start_) wait_start_ = now;
    if ((now - *wait_start_).toSec() < sync_timeout_s_) return true;
    NODELET_WARN_THROTTLE(10, "simulator: no answer on the sync topic for %.1f s: going on",
                          sync_timeout_s_);
    wait_start_.reset();
    return false;
  }

  void stepCb(const ros::WallTimerEvent&) {
    if (waitForPipeline()) return;
    const bool fresh =
        have_cmd_ && icgm::DurationSeconds(sim_->stamp(), cmd_stamp_) <= cmd_timeout_s_;
    sim_->Step(fresh ? cmd_ : icgm::VelocityCommand(), step_s_);
    out_->PublishStep(*sim_);
    if (sim_->num_steps() % steps_per_frame_ == 0) publishFrame();
  }

  void publishFrame() {
    const icgm::sim::SimFrame f = sim_->Render();
    frame_stamps_.push_back(f.stamp);
    if (frame_stamps_.size() > 16) frame_stamps_.pop_front();
    out_->PublishFrame(*sim_, f);
  }

  // Subscriptions
  ros::Subscriber cmd_sub_, sync_sub_;
  // Publications
  std::unique_ptr<icgm::nodelets::SimPublishers> out_;
  ros::WallTimer timer_;
  // Parameters
  double rate_factor_ = 1.0, step_s_ = 0.05, cmd_timeout_s_ = 0.5, sync_timeout_s_ = 2.0;
  int sync_lag_frames_ = 2;
  // State (callbacks run on the nodelet's single-threaded queue)
  std::unique_ptr<icgm::sim::ClosedLoopSimulator> sim_;
  int steps_per_frame_ = 1;
  icgm::VelocityCommand cmd_;
  icgm::Time cmd_stamp_;
  bool have_cmd_ = false;
  std::deque<icgm::Time> frame_stamps_;  // of the last frames published
  icgm::Time answered_;                  // latest stamp seen on the sync topic
  std::optional<ros::WallTime> wait_start_;
};

}  // namespace icgm_slam

PLUGINLIB_EXPORT_CLASS(icgm_slam::SimulatorNodelet, nodelet::Nodelet)
