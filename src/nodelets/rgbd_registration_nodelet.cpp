// RGB-D registration nodelet: the features of each frame (from the feature extraction nodelet)
// + registered depth + camera_info -> relative 6D pose of the camera since the previous frame
// (icgm_slam/RegistrationResult). Registration runs frame-to-keyframe in the core front end
// (descriptor matching -> ICGM -> RANSAC + Horn on depth -> refinement), as the offline tools
// do. A failed registration is published too, with its reason, so the fusion can fall back to
// wheel odometry for that span. The front end's keyframes (its choice of metric models, with
// the ICGM flags of their registration) go out on `keyframes` while someone listens: the map
// builder nodelet adds them to the map as icgm_slam_offline adds the same front end's. With
// ~map_config_file's map_features.source = tracker they carry the robust feature tracker's flags
// and leave one frame late, as in SlamSystem (core MapFeatureTracking); a keyframe still held
// after ~keyframe_hold_max_s of wall time without frames (end of a bag) leaves with the
// backward half of its window, as at the end of icgm_slam_offline.
//
// Live equals offline: the front end gets the same inputs as in icgm_slam_offline. Wheel
// odometry (nav_msgs/Odometry on `wheel_odom`) feeds RgbdFrontend::AddWheelOdometry, so ICGM's
// wheel motion prior and the vision/wheel gate run here too; the base -> camera extrinsic comes
// from tf (extrinsic_source.h: held input while it is missing, never an assumed identity). As
// offline, a frame is processed once wheel samples up to ~wheel_lead_s after its stamp are in
// (bounded by ~max_wait_for_wheel_s of message time, or of wall time when no newer message
// comes, e.g. at the end of a bag), and only those samples are given to the front end before
// it. With ~camera_only (hand-held camera) no wheels are expected.
#include <algorithm>
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

#include "core/common/option_reader.h"
#include "core/odometry/rgbd_frontend.h"
#include "core/odometry/vision_step.h"
#include "core/slam/map_feature_tracking.h"
#include "core/slam/wheel_feed.h"
#include "core/slam/wheel_paced_queue.h"
#include "nodelets/cpu_meter.h"
#include "nodelets/extrinsic_source.h"
#include "nodelets/features_depth_sync.h"
#include "nodelets/image_buffer.h"
#include "nodelets/nodelet_params.h"
#include "ros_bridge/conversions.h"
#include "ros_bridge/feature_msgs.h"
#include "ros_bridge/keyframe_msgs.h"
#include "ros_bridge/registration_msgs.h"

namespace icgm_slam {

class RgbdRegistrationNodelet : public nodelet::Nodelet {
 private:
  using Features = icgm_slam::RobustFeatures;
  using Image = sensor_msgs::Image;
  using Info = sensor_msgs::CameraInfo;
  struct Pending {  // a frame waiting for its wheel data
    Features::ConstPtr features;
    Image::ConstPtr depth;
    Info::ConstPtr info;
  };

  void onInit() override {
    namespace nodelets = icgm::nodelets;
    ros::NodeHandle& nh = getNodeHandle();
    ros::NodeHandle& pnh = getPrivateNodeHandle();
    // Parameters
    camera_ = std::make_unique<nodelets::CameraModelReader>(pnh, "rgbd registration");
    wheel_ = std::make_unique<icgm::WheelFeed>(nodelets::Param(pnh, "wheel_lead_s", 0.05));
    icgm::WheelPacedQueueOptions pacing;  // as icgm_slam_offline feeds the wheels
    pacing.max_wait_s = nodelets::Param(pnh, "max_wait_for_wheel_s", pacing.max_wait_s);
    pacing.max_pending =
        static_cast<size_t>(std::max(1, nodelets::Param(pnh, "max_pending_frames", 100)));
    keyframe_hold_max_s_ = nodelets::Param(pnh, "keyframe_hold_max_s", keyframe_hold_max_s_);
    nodelets::LoadConfiguration("rgbd registration", [&] {
      const std::string config_file = nodelets::Param(pnh, "config_file", "");
      const std::string icgm_file = nodelets::Param(pnh, "icgm_config_file", "");
      // map.yaml: which features the keyframes bring to the map
      const std::string map_config_file = nodelets::Param(pnh, "map_config_file", "");
      if (!config_file.empty()) {
        const auto odometry = icgm::OptionReader::FromFile(config_file);
        icgm::ReadFrontendOptions(
            odometry, icgm_file.empty() ? odometry : icgm::OptionReader::FromFile(icgm_file),
            &options_);
      }
      if (!map_config_file.empty()) {
        map_features_options_ = icgm::LoadMapFeatureOptions(
            map_config_file, icgm_file.empty() ? config_file : icgm_file);
      }
    });
    extrinsic_ = std::make_unique<nodelets::ExtrinsicSource>(
        pnh, nodelets::ReadFrameNames(pnh).base, options_.fusion.base_to_camera,
        "rgbd registration");
    pacing.wheels = !extrinsic_->camera_only();
    pending_ = std::make_unique<icgm::WheelPacedQueue<Pending>>(pacing, wheel_.get());
    // Publications
    result_pub_ = nh.advertise<icgm_slam::RegistrationResult>("relative_pose", 20);
    keyframe_pub_ = nh.advertise<icgm_slam::Keyframe>("keyframes", 20);
    // Subscriptions (eager: the previous frame is state)
    sync_ = std::make_unique<nodelets::FeaturesDepthSync>(
        nh, nodelets::Param(pnh, "queue_size", 10), nodelets::Param(pnh, "approx_sync", true),
        [this](const Features::ConstPtr& f, const Image::ConstPtr& d, const Info::ConstPtr& i) {
          frameCb(f, d, i);
        });
    if (!extrinsic_->camera_only()) {
      wheel_sub_ = nh.subscribe("wheel_odom", 400, &RgbdRegistrationNodelet::wheelCb, this);
    }
    // The colour image, only for the hypotheses' edge evidence (frontend.select_by_evidence).
    if (options_.select_by_evidence) {
      image_sub_ = nh.subscribe<Image>("image", 10, [this](const Image::ConstPtr& msg) {
        std::lock_guard<std::mutex> lock(mutex_);
        images_.Add(msg);
      });
    }
    flush_timer_ = nh.createWallTimer(ros::WallDuration(0.1), [this](const ros::WallTimerEvent&) {
      std::lock_guard<std::mutex> lock(mutex_);
      drain();
      flushHeldKeyframe();
    });
  }

  // The nodelet's callbacks may run on several threads; wheelCb and frameCb share the queues.
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

  void frameCb(const Features::ConstPtr& features_msg, const Image::ConstPtr& depth_msg,
               const Info::ConstPtr& info_msg) {
    std::lock_guard<std::mutex> lock(mutex_);
    if (!pending_->Push(icgm::ros_bridge::FromRos(features_msg->header.stamp),
                        {features_msg, depth_msg, info_msg})) {
      NODELET_WARN_THROTTLE(5.0, "rgbd registration: too many frames pending; oldest dropped");
    }
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
    if (icgm::Status s = camera_->Read(*p.info, &k); !s) {
      NODELET_WARN_THROTTLE(5.0, "rgbd registration: bad camera_info: %s", s.reason().c_str());
      pending_->PopFront();
      return false;
    }
    icgm::FrontendOptions options = options_;
    options.fusion.base_to_camera = *base_to_camera;
    frontend_ = std::make_unique<icgm::RgbdFrontend>(options, k);
    frontend_->SetKeyframeCallback(
        [this](const icgm::KeyframePtr& keyframe) { new_keyframe_ = keyframe; });
    map_features_ = std::make_unique<icgm::MapFeatureTracking>(map_features_options_);
    NODELET_INFO("rgbd registration: started (extrinsic from %s; %s)", extrinsic_->origin(),
                 k.HasDistortion() ? "lens distortion from camera_info undone"
                                   : "pinhole camera_info, no distortion");
    return true;
  }

  void process(const Pending& p) {
    const Features::ConstPtr& features_msg = p.features;
    last_frame_ = p;
    const Image::ConstPtr& depth_msg = p.depth;
    icgm::TrackedFrame frame;
    if (icgm::Status s = icgm::ros_bridge::FromFeaturesMsg(*features_msg, &frame); !s) {
      NODELET_WARN_THROTTLE(5.0, "rgbd registration: bad features: %s", s.reason().c_str());
      return;
    }
    cv::Mat depth_m;
    if (icgm::Status s =
            icgm::ros_bridge::DepthFromImageMsg(*depth_msg, camera_->depth_scale(), &depth_m);
        !s) {
      NODELET_WARN_THROTTLE(5.0, "rgbd registration: bad depth: %s", s.reason().c_str());
      return;
    }
    const cv::Mat bgr =
        options_.select_by_evidence ? images_.Find(features_msg->header.stamp) : cv::Mat();
    if (options_.select_by_evidence && bgr.empty()) {
      NODELET_WARN_THROTTLE(10.0, "rgbd registration: %zu frames without their colour image: "
                                  "motion hypotheses scored on depth alone", images_.missing());
    }
    const icgm::FrontendFrameResult r =
        frontend_->ProcessFeatures(frame.stamp, std::move(frame.features), depth_m,
                                   icgm::ros_bridge::FromRos(depth_msg->header.stamp), bgr,
                                   features_msg->keypoints_undistorted);
    // The keyframe entering the map now (one frame late with map_features.source tracker).
    last_frame_wall_ = ros::WallTime::now();
    publishKeyframe(map_features_->AfterFrame(*frontend_, std::move(new_keyframe_)), p);
    new_keyframe_.reset();
    if (!r.status.ok()) {
      NODELET_WARN_THROTTLE(5.0, "rgbd registration: frame dropped: %s", r.status.reason().c_str());
      return;
    }
    if (const auto step = steps_.Add(r)) {
      // A shared pointer: the fusion nodelet in the same manager gets it without serialization.
      result_pub_.publish(boost::make_shared<icgm_slam::RegistrationResult>(
          icgm::ros_bridge::ToRegistrationMsg(step->result, step->stamp, step->reference_stamp,
                                              features_msg->header.frame_id)));
    }
  }

  void publishKeyframe(const std::optional<icgm::FrontendKeyframe>& keyframe, const Pending& p) {
    if (!keyframe || keyframe_pub_.getNumSubscribers() == 0) return;
    // A shared pointer: the map builder in the same manager gets it without serialization.
    auto msg = boost::make_shared<icgm_slam::Keyframe>(
        icgm::ros_bridge::ToKeyframeMsg(*keyframe, p.features->header.frame_id, *p.info));
    msg->map_features_source = icgm::NameOf(map_features_options_.source);
    keyframe_pub_.publish(msg);
  }

  // A keyframe held for its next frame when no frame came for ~keyframe_hold_max_s.
  void flushHeldKeyframe() {
    if (!map_features_ || !map_features_->holding() || !last_frame_ ||
        ros::WallTime::now() - last_frame_wall_ < ros::WallDuration(keyframe_hold_max_s_)) {
      return;
    }
    NODELET_INFO("rgbd registration: no frame for %.1f s: the held keyframe goes to the map "
                 "with the backward half of its window", keyframe_hold_max_s_);
    publishKeyframe(map_features_->Flush(), *last_frame_);
  }

  // Subscriptions
  std::unique_ptr<icgm::nodelets::FeaturesDepthSync> sync_;
  ros::Subscriber wheel_sub_;
  ros::Subscriber image_sub_;  // with frontend.select_by_evidence
  ros::WallTimer flush_timer_;  // frames whose wheel data never comes (end of a bag)
  // Publications
  ros::Publisher result_pub_;
  ros::Publisher keyframe_pub_;
  // Parameters
  std::unique_ptr<icgm::nodelets::CameraModelReader> camera_;
  icgm::FrontendOptions options_;
  std::unique_ptr<icgm::nodelets::ExtrinsicSource> extrinsic_;
  // State
  std::mutex mutex_;
  icgm::nodelets::CpuMeter cpu_;
  std::unique_ptr<icgm::RgbdFrontend> frontend_;
  std::unique_ptr<icgm::WheelPacedQueue<Pending>> pending_;  // frames waiting for wheel data
  icgm::nodelets::ImageBuffer images_;  // recent colour images (select_by_evidence)
  std::unique_ptr<icgm::WheelFeed> wheel_;  // samples not yet given to frontend_
  icgm::VisionStepChain steps_;  // relative poses between processed frames
  // Map features (map_features.source of ~map_config_file): keyframes held one frame.
  icgm::MapFeatureOptions map_features_options_;
  double keyframe_hold_max_s_ = 0.5;
  std::unique_ptr<icgm::MapFeatureTracking> map_features_;
  icgm::KeyframePtr new_keyframe_;  // made by the front end during the current frame
  std::optional<Pending> last_frame_;
  ros::WallTime last_frame_wall_;
};

}  // namespace icgm_slam

PLUGINLIB_EXPORT_CLASS(icgm_slam::RgbdRegistrationNodelet, nodelet::Nodelet)
