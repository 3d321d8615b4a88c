// Odometry fusion nodelet: relative poses from RGB-D registration + wheel odometry -> fused
// odometry (nav_msgs/Odometry) and tf odom -> base_link (REP-105). Where registration failed,
// the wheel odometry's motion over the same span (interpolated at the image stamps) is used, as
// in thesis ch. 6.1.1.1; wheel data that jumps, stalls or runs backwards is refused by the core.
// The fusion itself is core LiveFusion (results in order, a failed registration waiting bounded
// for wheel data). The base -> camera extrinsic comes from tf, waited for (extrinsic_source.h),
// never guessed; results are held meanwhile. The pose covariance is the registration
// covariances (and a per-step model for wheel and constant-velocity steps) chained in the
// message's convention; the twist is the base's velocity over the last step
// (fused_odometry_outputs.h).
#include <memory>
#include <mutex>
#include <optional>
#include <string>

#include <nav_msgs/Odometry.h>
#include <nodelet/nodelet.h>
#include <ros/ros.h>
#include <pluginlib/class_list_macros.hpp>

#include "core/common/option_reader.h"
#include "core/odometry/live_fusion.h"
#include "nodelets/extrinsic_source.h"
#include "nodelets/fused_odometry_outputs.h"
#include "nodelets/nodelet_params.h"
#include "ros_bridge/conversions.h"
#include "ros_bridge/registration_msgs.h"

namespace icgm_slam {

class OdometryFusionNodelet : public nodelet::Nodelet {
 private:
  void onInit() override {
    namespace nodelets = icgm::nodelets;
    ros::NodeHandle& nh = getNodeHandle();
    ros::NodeHandle& pnh = getPrivateNodeHandle();
    // Parameters
    const nodelets::FrameNames frames = nodelets::ReadFrameNames(pnh);
    icgm::FusionQueueOptions queue;
    queue.max_wait_for_wheel_s = nodelets::Param(pnh, "max_wait_for_wheel_s", 0.3);
    icgm::FusionOptions fusion;
    icgm::WheelOdometryOptions wheel;
    nodelets::LoadConfiguration("odometry fusion", [&] {
      const std::string config_file = nodelets::Param(pnh, "config_file", "");
      if (config_file.empty()) return;
      const auto root = icgm::OptionReader::FromFile(config_file);
      icgm::ReadOptions(root.Section("fusion"), &fusion);
      icgm::ReadOptions(root.Section("wheel_odometry"), &wheel);
    });
    live_ = std::make_unique<icgm::LiveFusion>(fusion, wheel, queue);
    extrinsic_ = std::make_unique<nodelets::ExtrinsicSource>(
        pnh, frames.base, fusion.base_to_camera, "odometry fusion");
    // Publications
    outputs_ = std::make_unique<nodelets::FusedOdometryOutputs>(nh, pnh, frames);
    // Subscriptions (eager: the fused pose is state)
    if (!extrinsic_->camera_only()) {
      wheel_sub_ = nh.subscribe("wheel_odom", 200, &OdometryFusionNodelet::wheelCb, this);
    }
    result_sub_ = nh.subscribe("relative_pose", 50, &OdometryFusionNodelet::resultCb, this);
    icgm::nodelets::WarnUnknownParams(getPrivateNodeHandle(), "odometry fusion");
  }

  void wheelCb(const nav_msgs::Odometry::ConstPtr& msg) {
    std::lock_guard<std::mutex> lock(mutex_);
    const icgm::Status s = live_->AddWheelOdometry(icgm::ros_bridge::FromRos(msg->header.stamp),
                                                   icgm::ros_bridge::FromPoseMsg(msg->pose.pose));
    if (!s.ok())
      NODELET_WARN_THROTTLE(5.0, "odometry fusion: wheel odometry: %s", s.reason().c_str());
    if (live_->started()) drain();  // the start waits for a result
  }

  void resultCb(const icgm_slam::RegistrationResult::ConstPtr& msg) {
    std::lock_guard<std::mutex> lock(mutex_);
    if (live_->waiting() == 0) camera_frame_ = msg->header.frame_id;  // the oldest waiting one's
    live_->Push(icgm::ros_bridge::FromRos(msg->header.stamp),
                icgm::ros_bridge::FromRos(msg->reference_stamp),
                icgm::ros_bridge::FromRegistrationMsg(*msg));
    drain();
  }

  // The fusion starts at the first result's reference frame, once the extrinsic is known.
  bool start() {
    if (live_->waiting() == 0) return false;
    const std::optional<icgm::Pose3> base_to_camera = extrinsic_->Poll(camera_frame_);
    if (!base_to_camera) {
      if (extrinsic_->expired()) live_->Clear();  // nothing to place them with
      return false;
    }
    const icgm::Time stamp = *live_->Start(*base_to_camera);
    const std::string child_frame = extrinsic_->BaseFrame(camera_frame_);
    NODELET_INFO("odometry fusion: started (extrinsic from %s, child frame %s)",
                 extrinsic_->origin(), child_frame.c_str());
    outputs_->Start(icgm::ros_bridge::ToRos(stamp), *live_->fusion(), child_frame);
    return true;
  }

  void drain() {
    if (!live_->started() && !start()) return;
    live_->Drain([this](const icgm::FusedResult& f) { outputs_->Publish(f, *live_->fusion()); },
                 [this](icgm::Time stamp) {
                   NODELET_WARN("odometry fusion: time went backwards (%s); result dropped",
                                stamp.ToString().c_str());
                 });
  }

  // Subscriptions
  ros::Subscriber wheel_sub_;
  ros::Subscriber result_sub_;
  // Publications
  std::unique_ptr<icgm::nodelets::FusedOdometryOutputs> outputs_;  // odom, tf
  // Parameters
  std::unique_ptr<icgm::nodelets::ExtrinsicSource> extrinsic_;
  // State
  std::mutex mutex_;
  std::unique_ptr<icgm::LiveFusion> live_;
  std::string camera_frame_;  // of the oldest waiting result
};

}  // namespace icgm_slam

PLUGINLIB_EXPORT_CLASS(icgm_slam::OdometryFusionNodelet, nodelet::Nodelet)
