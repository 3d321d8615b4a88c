// Simulator nodelet: drives the closed-loop simulator (core/sim/closed_loop_simulator.h) with
// velocity commands (cmd_vel, geometry_msgs/Twist) and publishes what the robot's sensors give,
// under the names the pipeline and the recorded bags use (ros_bridge/topics.h): colour, depth and
// camera_info at the scenario's frame rate, wheel odometry (/odom, tf odom -> base_link) and
// /clock every step, the base -> camera extrinsic on /tf_static (latched). Ground truth for
// evaluation: the camera pose (/ground_truth/pose), the dynamic mask (only while subscribed), the
// walkers (/ground_truth/people) and the collision status (sim/status). ~num_pedestrians
// (>= 0) replaces the scenario's number of walkers.
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

#include <geometry_msgs/PoseArray.h>
#include <geometry_msgs/PoseStamped.h>
#include <geometry_msgs/Twist.h>
#include <nav_msgs/Odometry.h>
#include <nodelet/nodelet.h>
#include <ros/ros.h>
#include <rosgraph_msgs/Clock.h>
#include <sensor_msgs/CameraInfo.h>
#include <sensor_msgs/Image.h>
#include <tf2_msgs/TFMessage.h>
#include <pluginlib/class_list_macros.hpp>

#include <icgm_slam/SimStatus.h>

#include "core/sim/closed_loop_simulator.h"
#include "core/sim/sim_export.h"
#include "ros_bridge/conversions.h"
#include "ros_bridge/navigation_msgs.h"
#include "ros_bridge/sim_msgs.h"
#include "ros_bridge/topics.h"

namespace icgm_slam {

namespace topics = icgm::ros_bridge::topics;

class SimulatorNodelet : public nodelet::Nodelet {
 private:
  void onInit() override {
    ros::NodeHandle& nh = getNodeHandle();
    ros::NodeHandle& pnh = getPrivateNodeHandle();
    // Parameters
    std::string scenario;
    pnh.param<std::string>("scenario", scenario, "");
    int num_pedestrians = -1;  // < 0: the scenario's
    pnh.param("num_pedestrians", num_pedestrians, -1);
    pnh.param("rate_factor", rate_factor_, 1.0);
    pnh.param("step_s", step_s_, 0.05);
    pnh.param("cmd_timeout_s", cmd_timeout_s_, 0.5);
    pnh.param<std::string>("depth_encoding", depth_encoding_, "16UC1");
    std::string sync_topic;
    pnh.param<std::string>("sync_topic", sync_topic, "");
    pnh.param("sync_lag_frames", sync_lag_frames_, 2);
    pnh.param("sync_timeout_s", sync_timeout_s_, 2.0);
    pnh.param<std::string>("world_frame", world_frame_, topics::kWorldFrame);
    pnh.param<std::string>("odom_frame", odom_frame_, topics::kOdomFrame);
    pnh.param<std::string>("base_frame", base_frame_, topics::kBaseFrame);
    pnh.param<std::string>("camera_frame", camera_frame_, topics::kCameraFrame);
    try {
      if (scenario.empty()) throw icgm::LoadError("~scenario (a sim YAML) is not set");
      if (!(rate_factor_ > 0) || !(step_s_ > 0) || !(cmd_timeout_s_ > 0)) {
        throw icgm::LoadError("~rate_factor, ~step_s and ~cmd_timeout_s must be positive");
      }
      if (depth_encoding_ != "16UC1" && depth_encoding_ != "32FC1") {
        throw icgm::LoadError("~depth_encoding must be 16UC1 or 32FC1");
      }
      icgm::sim::SimOptions options = icgm::sim::LoadSimOptions(scenario);
      if (num_pedestrians >= 0) options.crowd.num_pedestrians = num_pedestrians;
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
    clock_pub_ = nh.advertise<rosgraph_msgs::Clock>("/clock", 10);
    rgb_pub_ = nh.advertise<sensor_msgs::Image>(topics::kRgbImage, 5);
    rgb_info_pub_ = nh.advertise<sensor_msgs::CameraInfo>(topics::kRgbInfo, 5);
    depth_pub_ = nh.advertise<sensor_msgs::Image>(
        depth_encoding_ == "16UC1" ? topics::kDepthImageMm : topics::kDepthImageM, 5);
    depth_info_pub_ = nh.advertise<sensor_msgs::CameraInfo>(topics::kDepthInfo, 5);
    mask_pub_ = nh.advertise<sensor_msgs::Image>(topics::kDynamicMask, 5);
    odom_pub_ = nh.advertise<nav_msgs::Odometry>(topics::kWheelOdom, 50);
    tf_pub_ = nh.advertise<tf2_msgs::TFMessage>(topics::kTf, 50);
    tf_static_pub_ = nh.advertise<tf2_msgs::TFMessage>(topics::kTfStatic, 1, true);
    gt_pub_ = nh.advertise<geometry_msgs::PoseStamped>(topics::kGroundTruthPose, 10);
    people_pub_ = nh.advertise<geometry_msgs::PoseArray>("/ground_truth/people", 5);
    status_pub_ = nh.advertise<icgm_slam::SimStatus>("sim/status", 50);
    // Subscriptions
    cmd_sub_ = nh.subscribe("cmd_vel", 10, &SimulatorNodelet::cmdCb, this);
    if (!sync_topic.empty()) {
      sync_sub_ = nh.subscribe<nav_msgs::Odometry>(
          sync_topic, 50, [this](const nav_msgs::Odometry::ConstPtr& m) {
            answered_ = std::max(answered_, icgm::ros_bridge::FromRos(m->header.stamp));
          });
    }

    publishTf(sim_->T_base_camera(), base_frame_, camera_frame_, tf_static_pub_);
    publishStep();
    publishFrame();
    timer_ = nh.createWallTimer(ros::WallDuration(step_s_ / rate_factor_),
                                &SimulatorNodelet::stepCb, this);
    NODELET_INFO(
        "simulator: %s, %zu walkers, frames at %.1f Hz, steps of %.3f s at %.2fx real time",
        scenario.c_str(), sim_->num_pedestrians(), sim_->options().frame_rate_hz, step_s_,
        rate_factor_);
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
    publishStep();
    if (sim_->num_steps() % steps_per_frame_ == 0) publishFrame();
  }

  // Every step: the clock first (nodes on sim time), then the wheels and the ground truth.
  void publishStep() {
    rosgraph_msgs::Clock clock;
    clock.clock = icgm::ros_bridge::ToRos(sim_->stamp());
    clock_pub_.publish(clock);
    icgm::ros_bridge::OdometryData odom;
    odom.stamp = sim_->stamp();
    odom.pose = sim_->odometry().T_odom_base;
    odom.linear_velocity_mps = sim_->odometry().linear_velocity_mps;
    odom.angular_velocity_rps = sim_->odometry().angular_velocity_rps;
    odom_pub_.publish(icgm::ros_bridge::ToOdometryMsg(odom, odom_frame_, base_frame_));
    publishTf(odom.pose, odom_frame_, base_frame_, tf_pub_);
    status_pub_.publish(icgm::ros_bridge::ToSimStatusMsg(*sim_, world_frame_));
  }

  void publishFrame() {
    const icgm::sim::SimFrame f = sim_->Render();
    frame_stamps_.push_back(f.stamp);
    if (frame_stamps_.size() > 16) frame_stamps_.pop_front();
    const icgm::CameraIntrinsics& K = sim_->intrinsics();
    namespace rb = icgm::ros_bridge;
    rgb_pub_.publish(rb::ToImageMsg(f.bgr, "bgr8", camera_frame_, f.stamp));
    rgb_info_pub_.publish(rb::ToCameraInfo(K, camera_frame_, f.stamp));
    if (depth_encoding_ == "16UC1") {
      depth_pub_.publish(rb::ToImageMsg(icgm::sim::DepthToMillimetres(f.depth_m), "16UC1",
                                        camera_frame_, f.stamp));
    } else {
      depth_pub_.publish(rb::ToImageMsg(f.depth_m, "32FC1", camera_frame_, f.stamp));
    }
    depth_info_pub_.publish(rb::ToCameraInfo(K, camera_frame_, f.stamp));
    if (mask_pub_.getNumSubscribers() > 0) {
      mask_pub_.publish(rb::ToImageMsg(f.dynamic_mask, "mono8", camera_frame_, f.stamp));
    }
    geometry_msgs::PoseStamped gt;
    gt.header.stamp = rb::ToRos(f.stamp);
    gt.header.frame_id = world_frame_;
    gt.pose = rb::ToPoseMsg(f.T_world_camera);
    gt_pub_.publish(gt);
    people_pub_.publish(rb::ToPeopleMsg(sim_->pedestrians(), world_frame_, f.stamp));
  }

  void publishTf(const icgm::Pose3& pose, const std::string& parent, const std::string& child,
                 const ros::Publisher& pub) {
    tf2_msgs::TFMessage m;
    m.transforms.resize(1);
    m.transforms[0].header.stamp = icgm::ros_bridge::ToRos(sim_->stamp());
    m.transforms[0].header.frame_id = parent;
    m.transforms[0].child_frame_id = child;
    m.transforms[0].transform = icgm::ros_bridge::ToTransformMsg(pose);
    pub.publish(m);
  }

  // Subscriptions
  ros::Subscriber cmd_sub_, sync_sub_;
  // Publications
  ros::Publisher clock_pub_, rgb_pub_, rgb_info_pub_, depth_pub_, depth_info_pub_, mask_pub_;
  ros::Publisher odom_pub_, tf_pub_, tf_static_pub_, gt_pub_, people_pub_, status_pub_;
  ros::WallTimer timer_;
  // Parameters
  double rate_factor_ = 1.0, step_s_ = 0.05, cmd_timeout_s_ = 0.5, sync_timeout_s_ = 2.0;
  int sync_lag_frames_ = 2;
  std::string depth_encoding_, world_frame_, odom_frame_, base_frame_, camera_frame_;
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
