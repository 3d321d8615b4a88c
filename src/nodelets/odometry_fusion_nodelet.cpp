// Odometry fusion nodelet: relative poses from RGB-D registration + wheel odometry -> fused
// odometry (nav_msgs/Odometry) and tf odom -> base_link (REP-105). Where registration failed,
// the wheel odometry's motion over the same span (interpolated at the image stamps) is used, as
// in thesis ch. 6.1.1.1; wheel data that jumps, stalls or runs backwards is refused by the core.
// The base -> camera extrinsic comes from tf, waited for (extrinsic_source.h), never guessed;
// results are held meanwhile. The pose covariance is the registration covariances (and a
// per-step model for wheel and constant-velocity steps) chained in the message's convention; the
// twist is the base's velocity over the last step, with that step's covariance carried through
// (odometry_covariance.h).
#include <memory>
#include <mutex>

#include <nav_msgs/Odometry.h>
#include <nodelet/nodelet.h>
#include <ros/ros.h>
#include <tf2_ros/transform_broadcaster.h>
#include <boost/make_shared.hpp>
#include <pluginlib/class_list_macros.hpp>

#include "core/common/option_reader.h"
#include "core/odometry/fusion_queue.h"
#include "core/odometry/odometry_fusion.h"
#include "nodelets/extrinsic_source.h"
#include "nodelets/nodelet_params.h"
#include "ros_bridge/conversions.h"
#include "ros_bridge/odometry_covariance.h"
#include "ros_bridge/registration_msgs.h"

namespace icgm_slam {

class OdometryFusionNodelet : public nodelet::Nodelet {
 private:
  void onInit() override {
    namespace nodelets = icgm::nodelets;
    ros::NodeHandle& nh = getNodeHandle();
    ros::NodeHandle& pnh = getPrivateNodeHandle();
    // Parameters
    frames_ = nodelets::ReadFrameNames(pnh);
    publish_tf_ = nodelets::Param(pnh, "publish_tf", true);
    icgm::FusionQueueOptions queue;
    queue.max_wait_for_wheel_s = nodelets::Param(pnh, "max_wait_for_wheel_s", 0.3);
    queue_ = icgm::FusionQueue(queue);
    // Covariance of steps not measured by vision: sigma = floor + share of the step length.
    fallback_.floor_m = nodelets::Param(pnh, "fallback_sigma_floor_m", fallback_.floor_m);
    fallback_.floor_rad = nodelets::Param(pnh, "fallback_sigma_floor_rad", fallback_.floor_rad);
    fallback_.per_m = nodelets::Param(pnh, "fallback_sigma_per_m", fallback_.per_m);
    icgm::WheelOdometryOptions wheel_options;
    nodelets::LoadConfiguration("odometry fusion", [&] {
      const std::string config_file = nodelets::Param(pnh, "config_file", "");
      if (config_file.empty()) return;
      const auto root = icgm::OptionReader::FromFile(config_file);
      icgm::ReadOptions(root.Section("fusion"), &fusion_options_);
      icgm::ReadOptions(root.Section("wheel_odometry"), &wheel_options);
    });
    wheel_ = std::make_unique<icgm::WheelOdometryBuffer>(wheel_options);
    extrinsic_ = std::make_unique<nodelets::ExtrinsicSource>(
        pnh, frames_.base, fusion_options_.base_to_camera, "odometry fusion");
    // Publications
    odom_pub_ = nh.advertise<nav_msgs::Odometry>("odom", 50);
    // Subscriptions (eager: the fused pose is state)
    if (!extrinsic_->camera_only()) {
      wheel_sub_ = nh.subscribe("wheel_odom", 200, &OdometryFusionNodelet::wheelCb, this);
    }
    result_sub_ = nh.subscribe("relative_pose", 50, &OdometryFusionNodelet::resultCb, this);
  }

  void wheelCb(const nav_msgs::Odometry::ConstPtr& msg) {
    std::lock_guard<std::mutex> lock(mutex_);
    const icgm::Status s = wheel_->Add(icgm::ros_bridge::FromRos(msg->header.stamp),
                                       icgm::ros_bridge::FromPoseMsg(msg->pose.pose));
    if (!s.ok()) NODELET_WARN_THROTTLE(5.0, "odometry fusion: wheel odometry: %s", s.reason().c_str());
    drain();
  }

  void resultCb(const icgm_slam::RegistrationResult::ConstPtr& msg) {
    std::lock_guard<std::mutex> lock(mutex_);
    if (queue_.empty()) first_ = msg;  // the oldest waiting result
    queue_.Push(icgm::ros_bridge::FromRos(msg->header.stamp),
                icgm::ros_bridge::FromRegistrationMsg(*msg));
    if (!fusion_ && !start()) return;
    drain();
  }

  // The fusion starts at the first result's reference frame, once the extrinsic is known.
  bool start() {
    const std::optional<icgm::Pose3> base_to_camera = extrinsic_->Poll(first_->header.frame_id);
    if (!base_to_camera) {
      if (extrinsic_->expired()) queue_.Clear();  // nothing to place them with
      return false;
    }
    icgm::FusionOptions options = fusion_options_;
    options.base_to_camera = *base_to_camera;
    child_frame_ = extrinsic_->BaseFrame(first_->header.frame_id);
    fusion_ = std::make_unique<icgm::OdometryFusion>(options);
    fusion_->Initialize(icgm::ros_bridge::FromRos(first_->reference_stamp), wheel_.get());
    NODELET_INFO("odometry fusion: started (extrinsic from %s, child frame %s)",
                 extrinsic_->origin(), child_frame_.c_str());
    // The start pose on tf (no odom message: nothing was measured), so the first frame's
    // pose can be looked up too (the map builder's first keyframe).
    publishTf(first_->reference_stamp);
    return true;
  }

  // Fuses the waiting results in order (core FusionQueue: a failed registration waits, bounded,
  // for wheel data covering its stamp so the fallback has something to interpolate).
  void drain() {
    if (!fusion_) return;
    queue_.Drain(
        fusion_.get(), *wheel_,
        [this](const icgm::FusedResult& f) {
          const icgm::Mat6 step_covariance =
              icgm::ros_bridge::FusedStepCovariance(f.step, f.registration->covariance, fallback_);
          covariance_.AddStep(f.odom_camera_before, fusion_->odom_camera(), step_covariance);
          if (f.step.source != icgm::MotionSource::kVision) {
            NODELET_DEBUG("odometry fusion: %s motion at %s (vision: %s; wheel: %s)",
                          icgm::MotionSourceName(f.step.source), f.stamp.ToString().c_str(),
                          f.registration->status.reason().c_str(),
                          f.step.wheel_status.reason().c_str());
          }
          publish(icgm::ros_bridge::ToRos(f.stamp),
                  icgm::ros_bridge::BaseStepTwist(f.step.camera_prev_cur, step_covariance,
                                                  fusion_->options().base_to_camera, f.dt_s));
        },
        [this](icgm::Time stamp) {
          NODELET_WARN("odometry fusion: time went backwards (%s); result dropped",
                       stamp.ToString().c_str());
        });
  }

  void publish(const ros::Time& stamp, const icgm::ros_bridge::StepTwist& twist) {
    const icgm::Pose3& base_to_camera = fusion_->options().base_to_camera;
    // A shared pointer: no serialization for subscribers in the same manager.
    odom_pub_.publish(boost::make_shared<nav_msgs::Odometry>(icgm::ros_bridge::ToFusedOdometryMsg(
        stamp, frames_.odom, child_frame_, fusion_->odom_base(),
        covariance_.BaseMsg(fusion_->odom_camera(), base_to_camera), twist)));
    publishTf(stamp);
    const auto& stats = fusion_->stats();
    if (stats.total_frames() % 100 == 0) {
      NODELET_INFO("odometry fusion: %zu frames, vision share %.1f%% of frames, %.1f%% of distance",
                   stats.total_frames(), 100 * stats.VisionShareByFrames(),
                   100 * stats.VisionShareByDistance());
    }
  }

  void publishTf(const ros::Time& stamp) {
    if (!publish_tf_) return;
    geometry_msgs::TransformStamped t;
    t.header.stamp = stamp;
    t.header.frame_id = frames_.odom;
    t.child_frame_id = child_frame_;
    t.transform = icgm::ros_bridge::ToTransformMsg(fusion_->odom_base());
    tf_broadcaster_.sendTransform(t);
  }

  // Subscriptions
  ros::Subscriber wheel_sub_;
  ros::Subscriber result_sub_;
  // Publications
  ros::Publisher odom_pub_;
  tf2_ros::TransformBroadcaster tf_broadcaster_;
  // Parameters
  icgm::nodelets::FrameNames frames_;
  bool publish_tf_ = true;
  icgm::ros_bridge::FallbackStepSigmas fallback_;
  icgm::FusionOptions fusion_options_;
  std::unique_ptr<icgm::nodelets::ExtrinsicSource> extrinsic_;
  // State
  std::mutex mutex_;
  std::string child_frame_;  // base_frame, or the camera frame in camera-only mode
  icgm::ros_bridge::OdometryCovariance covariance_;
  std::unique_ptr<icgm::WheelOdometryBuffer> wheel_;
  std::unique_ptr<icgm::OdometryFusion> fusion_;
  icgm::FusionQueue queue_;  // results waiting to be fused
  icgm_slam::RegistrationResult::ConstPtr first_;  // the oldest waiting result
};

}  // namespace icgm_slam

PLUGINLIB_EXPORT_CLASS(icgm_slam::OdometryFusionNodelet, nodelet::Nodelet)
