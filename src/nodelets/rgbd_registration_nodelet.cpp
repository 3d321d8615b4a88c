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
#include <cmath>
#include <deque>
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
#include "core/dataset/camera_options.h"
#include "core/odometry/rgbd_frontend.h"
#include "core/odometry/vision_step.h"
#include "core/slam/map_feature_tracking.h"
#include "core/slam/wheel_feed.h"
#include "core/slam/wheel_paced_queue.h"
#include "nodelets/cpu_meter.h"
#include "nodelets/extrinsic_source.h"
#include "nodelets/features_depth_sync.h"
#include "nodelets/sensor_calibration.h"
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
    ros::NodeHandle& nh = getNodeHandle();
    ros::NodeHandle& pnh = getPrivateNodeHandle();
    // Parameters
    std::string config_file;
    pnh.param<std::string>("config_file", config_file, "");
    pnh.param<std::string>("icgm_config_file", icgm_config_file_, "");
    std::string map_config_file;  // map.yaml: which features the keyframes bring to the map
    pnh.param<std::string>("map_config_file", map_config_file, "");
    pnh.param("keyframe_hold_max_s", keyframe_hold_max_s_, keyframe_hold_max_s_);
    int queue_size = 10;
    bool approx_sync = true;
    pnh.param("queue_size", queue_size, queue_size);
    pnh.param("approx_sync", approx_sync, approx_sync);
    pnh.param("depth_scale", depth_scale_, 1000.0);
    std::string base_frame;
    pnh.param<std::string>("base_frame", base_frame, "base_link");
    double wheel_lead_s = 0.05;  // as icgm_slam_offline feeds the wheels
    pnh.param("wheel_lead_s", wheel_lead_s, wheel_lead_s);
    wheel_ = std::make_unique<icgm::WheelFeed>(wheel_lead_s);
    icgm::WheelPacedQueueOptions pacing;
    pnh.param("max_wait_for_wheel_s", pacing.max_wait_s, pacing.max_wait_s);
    int max_pending_frames = 100;
    pnh.param("max_pending_frames", max_pending_frames, max_pending_frames);
    pacing.max_pending = static_cast<size_t>(std::max(1, max_pending_frames));
    // Depth timing and scale, rolling shutter: ~camera_config_file and single parameters.
    std::string calibration_error;
    sensor_calibration_ = icgm::nodelets::ReadSensorCalibration(pnh, &calibration_error);
    if (!calibration_error.empty()) {
      NODELET_ERROR("rgbd registration: %s (ignored)", calibration_error.c_str());
    }
    try {
      if (!config_file.empty()) {
        const auto odometry = icgm::OptionReader::FromFile(config_file);
        icgm::ReadFrontendOptions(odometry, icgm_config_file_.empty()
                                                ? odometry
                                                : icgm::OptionReader::FromFile(icgm_config_file_),
                                  &options_);
      }
      if (!map_config_file.empty()) {
        map_features_options_ = icgm::LoadMapFeatureOptions(
            map_config_file, icgm_config_file_.empty() ? config_file : icgm_config_file_);
      }
    } catch (const icgm::LoadError& e) {
      NODELET_FATAL("rgbd registration: bad configuration: %s", e.what());
      throw;
    }
    extrinsic_ = std::make_unique<icgm::nodelets::ExtrinsicSource>(
        pnh, base_frame, options_.fusion.base_to_camera, "rgbd registration");
    pacing.wheels = !extrinsic_->camera_only();
    pending_ = std::make_unique<icgm::WheelPacedQueue<Pending>>(pacing, wheel_.get());
    // Publications
    result_pub_ = nh.advertise<icgm_slam::RegistrationResult>("relative_pose", 20);
    keyframe_pub_ = nh.advertise<icgm_slam::Keyframe>("keyframes", 20);
    // Subscriptions (eager: the previous frame is state)
    sync_ = std::make_unique<icgm::nodelets::FeaturesDepthSync>(
        nh, queue_size, approx_sync,
        [this](const Features::ConstPtr& f, const Image::ConstPtr& d, const Info::ConstPtr& i) {
          frameCb(f, d, i);
        });
    if (!extrinsic_->camera_only()) {
      wheel_sub_ = nh.subscribe("wheel_odom", 400, &RgbdRegistrationNodelet::wheelCb, this);
    }
    // The colour image, only for the hypotheses' edge evidence (frontend.select_by_evidence).
    if (options_.select_by_evidence) {
      image_sub_ = nh.subscribe("image", 10, &RgbdRegistrationNodelet::imageCb, this);
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

  // The colour images, only for the hypotheses' edge evidence (frontend.select_by_evidence).
  void imageCb(const Image::ConstPtr& msg) {
    std::lock_guard<std::mutex> lock(mutex_);
    images_.push_back(msg);
    while (images_.size() > kMaxImages) images_.pop_front();
  }

  // The colour image stamped like the features (empty when it has not arrived).
  cv::Mat ImageFor(const ros::Time& stamp) {
    cv::Mat bgr;
    for (const Image::ConstPtr& m : images_) {
      if (m->header.stamp == stamp && icgm::ros_bridge::ColorFromImageMsg(*m, &bgr).ok()) return bgr;
    }
    NODELET_WARN_THROTTLE(10.0, "rgbd registration: %zu frames without their colour image: "
                                "motion hypotheses scored on depth alone", ++frames_without_image_);
    return cv::Mat();
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
    if (icgm::Status s = icgm::ros_bridge::FromCameraInfo(*p.info, depth_scale_, &k); !s) {
      NODELET_WARN_THROTTLE(5.0, "rgbd registration: bad camera_info: %s", s.reason().c_str());
      pending_->PopFront();
      return false;
    }
    icgm::CopySensorCalibration(sensor_calibration_, &k);
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
    if (icgm::Status s = icgm::ros_bridge::DepthFromImageMsg(*depth_msg, depth_scale_, &depth_m);
        !s) {
      NODELET_WARN_THROTTLE(5.0, "rgbd registration: bad depth: %s", s.reason().c_str());
      return;
    }
    const cv::Mat bgr =
        options_.select_by_evidence ? ImageFor(features_msg->header.stamp) : cv::Mat();
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
    if (previous_) {
      // A shared pointer: the fusion nodelet in the same manager gets it without serialization.
      result_pub_.publish(boost::make_shared<icgm_slam::RegistrationResult>(
          icgm::ros_bridge::ToRegistrationMsg(icgm::VisionStep(r, previous_->odom_camera), r.stamp,
                                              previous_->stamp, features_msg->header.frame_id)));
    }
    previous_ = Previous{r.stamp, r.odom_camera};
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

  struct Previous {
    icgm::Time stamp;
    icgm::Pose3 odom_camera;
  };

  // Subscriptions
  std::unique_ptr<icgm::nodelets::FeaturesDepthSync> sync_;
  ros::Subscriber wheel_sub_;
  ros::Subscriber image_sub_;  // with frontend.select_by_evidence
  ros::WallTimer flush_timer_;  // frames whose wheel data never comes (end of a bag)
  // Publications
  ros::Publisher result_pub_;
  ros::Publisher keyframe_pub_;
  // Parameters
  double depth_scale_ = 1000.0;
  icgm::CameraIntrinsics sensor_calibration_;  // camera_info lacks these fields
  std::string icgm_config_file_;
  icgm::FrontendOptions options_;
  std::unique_ptr<icgm::nodelets::ExtrinsicSource> extrinsic_;
  // State
  std::mutex mutex_;
  icgm::nodelets::CpuMeter cpu_;
  std::unique_ptr<icgm::RgbdFrontend> frontend_;
  std::unique_ptr<icgm::WheelPacedQueue<Pending>> pending_;  // frames waiting for wheel data
  static constexpr size_t kMaxImages = 100;
  std::deque<Image::ConstPtr> images_;  // recent colour images (select_by_evidence)
  size_t frames_without_image_ = 0;
  std::unique_ptr<icgm::WheelFeed> wheel_;  // samples not yet given to frontend_
  std::optional<Previous> previous_;
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
