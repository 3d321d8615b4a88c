// RGB-D registration nodelet: the features of each frame (from the feature extraction nodelet)
// + registered depth + camera_info -> relative 6D pose of the camera since the previous frame
// (icgm_slam/RegistrationResult). Registration runs frame-to-keyframe in the core front end
// (descriptor matching -> ICGM -> RANSAC + Horn on depth -> refinement), as the offline tools
// do. A failed registration is published too, with its reason, so the fusion can fall back to
// wheel odometry for that span. The front end's keyframes go to the map builder on `keyframes`
// (keyframe_outlet.h: held one frame with map_features.source tracker, released when the frames
// pause and flushed by the map builder's mode switch, as in SlamSystem).
//
// Live equals offline: the front end gets the same inputs as in icgm_slam_offline. Wheel
// odometry (nav_msgs/Odometry on `wheel_odom`) feeds RgbdFrontend::AddWheelOdometry, so ICGM's
// wheel motion prior and the vision/wheel gate run here too; the base -> camera extrinsic comes
// from tf (extrinsic_source.h: held input while it is missing, never an assumed identity). As
// offline, a frame is processed once wheel samples up to ~wheel_lead_s after its stamp are in
// (wheel_paced_queue.h, bounded by ~max_wait_for_wheel_s), and only those samples are given to
// the front end before it. With ~camera_only (hand-held camera) no wheels are expected.
// Parameters: registration_params.h.
#include <memory>
#include <mutex>
#include <optional>

#include <boost/make_shared.hpp>

#include <nav_msgs/Odometry.h>
#include <nodelet/nodelet.h>
#include <pluginlib/class_list_macros.hpp>
#include <ros/ros.h>
#include <sensor_msgs/CameraInfo.h>
#include <sensor_msgs/Image.h>

#include "core/odometry/rgbd_frontend.h"
#include "core/odometry/vision_step.h"
#include "core/slam/wheel_feed.h"
#include "core/slam/wheel_paced_queue.h"
#include "nodelets/cpu_meter.h"
#include "nodelets/extrinsic_source.h"
#include "nodelets/features_depth_sync.h"
#include "nodelets/frontend_frame.h"
#include "nodelets/image_buffer.h"
#include "nodelets/keyframe_outlet.h"
#include "nodelets/nodelet_params.h"
#include "nodelets/registration_params.h"
#include "ros_bridge/conversions.h"
#include "ros_bridge/registration_msgs.h"

namespace icgm_slam {

class RgbdRegistrationNodelet : public nodelet::Nodelet {
 private:
  using Features = icgm_slam::RobustFeatures;
  using Image = sensor_msgs::Image;
  using Info = sensor_msgs::CameraInfo;
  using Pending = icgm::nodelets::FrontendFrame;  // a frame waiting for its wheel data

  void onInit() override {
    namespace nodelets = icgm::nodelets;
    ros::NodeHandle& nh = getNodeHandle();
    ros::NodeHandle& pnh = getPrivateNodeHandle();
    // Parameters
    camera_ = std::make_unique<nodelets::CameraModelReader>(pnh, "rgbd registration");
    nodelets::LoadConfiguration("rgbd registration",
                                [&] { params_ = nodelets::ReadRegistrationParams(pnh); });
    wheel_ = std::make_unique<icgm::WheelFeed>(params_.wheel_lead_s);
    extrinsic_ = std::make_unique<nodelets::ExtrinsicSource>(
        pnh, nodelets::ReadFrameNames(pnh).base, params_.frontend.fusion.base_to_camera,
        "rgbd registration");
    params_.pacing.wheels = !extrinsic_->camera_only();
    pending_ = std::make_unique<icgm::WheelPacedQueue<Pending>>(params_.pacing, wheel_.get());
    // Publications
    result_pub_ = nh.advertise<icgm_slam::RegistrationResult>("relative_pose", 20);
    keyframes_ = std::make_unique<nodelets::KeyframeOutlet>(nh, params_.map_features,
                                                            params_.keyframe_hold_max_s);
    // Subscriptions (eager: the previous frame is state)
    sync_ = std::make_unique<nodelets::FeaturesDepthSync>(
        nh, params_.queue_size, params_.approx_sync,
        [this](const Features::ConstPtr& f, const Image::ConstPtr& d, const Info::ConstPtr& i) {
          std::lock_guard<std::mutex> lock(mutex_);
          if (!pending_->Push(icgm::ros_bridge::FromRos(f->header.stamp), {f, d, i})) {
            NODELET_WARN_THROTTLE(5.0, "rgbd registration: too many frames pending; oldest dropped");
          }
          drain();
        });
    if (!extrinsic_->camera_only()) {
      wheel_sub_ = nh.subscribe("wheel_odom", 400, &RgbdRegistrationNodelet::wheelCb, this);
    }
    // The colour image, only for the hypotheses' edge evidence (frontend.select_by_evidence).
    if (params_.frontend.select_by_evidence) {
      image_sub_ = nh.subscribe<Image>("image", 10, [this](const Image::ConstPtr& msg) {
        std::lock_guard<std::mutex> lock(mutex_);
        images_.Add(msg);
      });
    }
    flush_timer_ = nh.createWallTimer(ros::WallDuration(0.1), [this](const ros::WallTimerEvent&) {
      std::lock_guard<std::mutex> lock(mutex_);
      drain();
      if (keyframes_->ReleaseIfPaused()) {
        NODELET_INFO("rgbd registration: no frame for %.1f s: the held keyframe goes to the map "
                     "with the backward half of its window", keyframes_->hold_max_s());
      }
    });
  }

  // The nodelet's callbacks may run on several threads; wheelCb and the frames share the queues.
  void wheelCb(const nav_msgs::Odometry::ConstPtr& msg) {
    std::lock_guard<std::mutex> lock(mutex_);
    const icgm::Time stamp = icgm::ros_bridge::FromRos(msg->header.stamp);
    if (!wheel_->Add(stamp, icgm::ros_bridge::FromPoseMsg(msg->pose.pose))) {
      NODELET_WARN_THROTTLE(5.0, "rgbd registration: wheel odometry out of order; sample dropped");
      return;
    }
    pending_->Note(stamp);
    drain();
  }

  // Processes the pending frames in order, each once its wheel data is in (wheel_paced_queue.h).
  void drain() {
    while (Pending* p = pending_->ReadyFront()) {
      if (!frontend_ && !CreateFrontend(*p)) {
        if (extrinsic_->expired()) pending_->Clear();
        return;
      }
      if (!extrinsic_->camera_only() && !wheel_->received_any()) {
        NODELET_WARN_THROTTLE(10.0, "rgbd registration: no wheel odometry received; registering "
                                    "without the wheel motion prior (set ~camera_only for a "
                                    "camera without wheels)");
      }
      wheel_->FeedUpTo(pending_->front_stamp(), [this](icgm::Time t, const icgm::Pose3& pose) {
        if (const icgm::Status s = frontend_->AddWheelOdometry(t, pose); !s.ok()) {
          NODELET_WARN_THROTTLE(5.0, "rgbd registration: wheel odometry: %s", s.reason().c_str());
        }
      });
      cpu_.Start();
      process(*p);
      if (double ms; cpu_.Stop(&ms)) {
        NODELET_INFO("rgbd registration: %.1f ms CPU per frame (last 100)", ms);
      }
      pending_->PopFront();
    }
  }

  bool CreateFrontend(const Pending& p) {
    const std::optional<icgm::Pose3> base_to_camera = extrinsic_->Poll(p.features->header.frame_id);
    if (!base_to_camera) return false;
    icgm::CameraIntrinsics k;
    if (const icgm::Status s = icgm::nodelets::MakeFrontend(
            params_.frontend, *base_to_camera, *camera_, p, &new_keyframe_, &k, &frontend_);
        !s) {
      NODELET_WARN_THROTTLE(5.0, "rgbd registration: %s", s.reason().c_str());
      pending_->PopFront();
      return false;
    }
    NODELET_INFO("rgbd registration: started (extrinsic from %s; %s)", extrinsic_->origin(),
                 k.HasDistortion() ? "lens distortion from camera_info undone"
                                   : "pinhole camera_info, no distortion");
    return true;
  }

  void process(const Pending& p) {
    const bool evidence = params_.frontend.select_by_evidence;
    const cv::Mat bgr = evidence ? images_.Find(p.features->header.stamp) : cv::Mat();
    if (evidence && bgr.empty()) {
      NODELET_WARN_THROTTLE(10.0, "rgbd registration: %zu frames without their colour image: "
                                  "motion hypotheses scored on depth alone", images_.missing());
    }
    icgm::FrontendFrameResult r;
    if (const icgm::Status s = icgm::nodelets::RegisterFrame(p, camera_->depth_scale(), bgr,
                                                             frontend_.get(), &r);
        !s) {
      NODELET_WARN_THROTTLE(5.0, "rgbd registration: %s", s.reason().c_str());
      return;
    }
    keyframes_->AfterFrame(*frontend_, std::move(new_keyframe_), p.features->header.frame_id,
                           p.info);
    new_keyframe_.reset();
    if (!r.status.ok()) {
      NODELET_WARN_THROTTLE(5.0, "rgbd registration: frame dropped: %s", r.status.reason().c_str());
      return;
    }
    if (const auto step = steps_.Add(r)) {
      // A shared pointer: the fusion nodelet in the same manager gets it without serialization.
      result_pub_.publish(boost::make_shared<icgm_slam::RegistrationResult>(
          icgm::ros_bridge::ToRegistrationMsg(step->result, step->stamp, step->reference_stamp,
                                              p.features->header.frame_id)));
    }
  }

  // Subscriptions
  std::unique_ptr<icgm::nodelets::FeaturesDepthSync> sync_;
  ros::Subscriber wheel_sub_;
  ros::Subscriber image_sub_;  // with frontend.select_by_evidence
  ros::WallTimer flush_timer_;  // frames whose wheel data never comes; a pause (end of a bag)
  // Publications
  ros::Publisher result_pub_;
  std::unique_ptr<icgm::nodelets::KeyframeOutlet> keyframes_;
  // Parameters
  std::unique_ptr<icgm::nodelets::CameraModelReader> camera_;
  icgm::nodelets::RegistrationParams params_;
  std::unique_ptr<icgm::nodelets::ExtrinsicSource> extrinsic_;
  // State
  std::mutex mutex_;
  icgm::nodelets::CpuMeter cpu_;
  std::unique_ptr<icgm::RgbdFrontend> frontend_;
  std::unique_ptr<icgm::WheelPacedQueue<Pending>> pending_;  // frames waiting for wheel data
  icgm::nodelets::ImageBuffer images_;  // recent colour images (select_by_evidence)
  std::unique_ptr<icgm::WheelFeed> wheel_;  // samples not yet given to frontend_
  icgm::VisionStepChain steps_;  // relative poses between processed frames
  icgm::KeyframePtr new_keyframe_;  // made by the front end during the current frame
};

}  // namespace icgm_slam

PLUGINLIB_EXPORT_CLASS(icgm_slam::RgbdRegistrationNodelet, nodelet::Nodelet)
