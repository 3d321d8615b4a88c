// RGB-D registration nodelet: the features of each frame (from the feature extraction nodelet)
// + registered depth + camera_info -> relative 6D pose of the camera since the previous frame
// (icgm_slam/RegistrationResult). Registration runs frame-to-keyframe in the core front end
// (descriptor matching -> ICGM -> RANSAC + Horn on depth -> refinement), as the offline tools
// do. A failed registration is published too, with its reason, so the fusion can fall back to
// wheel odometry for that span. The front end's keyframes go to the map builder on `keyframes`
// (keyframe_outlet.h: held one frame with map_features.source tracker, released when the frames
// pause and flushed by the map builder's mode switch, as in SlamSystem).
//
// Live equals offline: core LiveFrontend (core/slam/live_frontend.h) paces the frames by the
// wheel odometry (nav_msgs/Odometry on `wheel_odom`) and gives the front end the same wheel
// samples before each frame as icgm_slam_offline, so ICGM's wheel motion prior and the
// vision/wheel gate run here too. The base -> camera extrinsic comes from tf
// (extrinsic_source.h: frames wait while it is missing, never an assumed identity). With
// ~camera_only (hand-held camera) no wheels are expected. Parameters: registration_params.h.
// camera_info is not synchronised with the frames: the latest one before the start is kept, the
// front end starts with it (its intrinsics are fixed from then on), the keyframes carry it, and
// the subscription ends there, so a frame brings two messages (features, depth) to the manager.
// Every frame taken from the input queues (features paired with depth) is
// announced on `taken_frames` (std_msgs/Header with its stamp): the feature extraction's
// backpressure counts the features still waiting in those queues (frames waiting for their
// wheel data are taken: they wait in LiveFrontend, which does not drop them).
// Frames paired (features with depth), refused (unreadable, or depth of another size than the
// camera_info: a throttled error names both sizes and the topic), dropped from the pending queue
// and processed are counted on /diagnostics (frame_counts.h).
#include <atomic>
#include <memory>
#include <mutex>
#include <string>

#include <nav_msgs/Odometry.h>
#include <nodelet/nodelet.h>
#include <ros/ros.h>
#include <sensor_msgs/CameraInfo.h>
#include <sensor_msgs/Image.h>
#include <std_msgs/Header.h>
#include <boost/make_shared.hpp>
#include <pluginlib/class_list_macros.hpp>

#include "core/dataset/depth_buffers.h"
#include "core/slam/live_frontend.h"
#include "nodelets/extrinsic_source.h"
#include "nodelets/features_depth_sync.h"
#include "nodelets/frame_counts.h"
#include "nodelets/frontend_frame.h"
#include "nodelets/image_buffer.h"
#include "nodelets/nodelet_params.h"
#include "nodelets/registration_outputs.h"
#include "nodelets/registration_params.h"
#include "ros_bridge/conversions.h"
#include "ros_bridge/image_size.h"

namespace icgm_slam {

class RgbdRegistrationNodelet : public nodelet::Nodelet {
 private:
  using Features = icgm_slam::RobustFeatures;
  using Image = sensor_msgs::Image;
  using Info = sensor_msgs::CameraInfo;

  void onInit() override {
    namespace nodelets = icgm::nodelets;
    ros::NodeHandle& nh = getNodeHandle();
    ros::NodeHandle& pnh = getPrivateNodeHandle();
    // Parameters
    camera_ = std::make_unique<nodelets::CameraModelReader>(pnh, "rgbd registration");
    nodelets::ApplyOpenCvThreads(pnh, "rgbd registration");
    nodelets::LoadConfiguration("rgbd registration",
                                [&] { params_ = nodelets::ReadRegistrationParams(pnh); });
    extrinsic_ = std::make_unique<nodelets::ExtrinsicSource>(
        pnh, nodelets::ReadFrameNames(pnh).base, params_.frontend.fusion.base_to_camera,
        "rgbd registration");
    params_.live.pacing.wheels = !extrinsic_->camera_only();
    live_ = std::make_unique<icgm::LiveFrontend>(params_.live);
    // Publications
    outputs_ = std::make_unique<nodelets::RegistrationOutputs>(nh, params_.map_features,
                                                               params_.keyframe_hold_max_s);
    taken_pub_ = nh.advertise<std_msgs::Header>("taken_frames", 20);
    counts_ = std::make_unique<nodelets::FrameCounts>(
        nh, getName(), std::vector<std::string>{"paired", "refused", "dropped", "processed"});
    // Subscriptions (eager: the previous frame is state)
    sync_ = std::make_unique<nodelets::FeaturesDepthSync>(
        nh, params_.queue_size, params_.approx_sync,
        [this](const Features::ConstPtr& f, const Image::ConstPtr& d) {
          counts_->Add(kPaired);
          if (taken_pub_.getNumSubscribers() > 0) {
            auto taken = boost::make_shared<std_msgs::Header>(f->header);
            taken_pub_.publish(taken);  // shared: no serialization in the manager
          }
          if (!depthFits(*d)) return;
          icgm::LiveFrame frame;
          {
            std::lock_guard<std::mutex> lock(buffers_mutex_);
            frame.depth_m =
                depth_buffers_.Take(static_cast<int>(d->height), static_cast<int>(d->width));
          }
          if (icgm::Status s = nodelets::ToLiveFrame(*f, *d, camera_->depth_scale(), &frame); !s) {
            counts_->Add(kRefused);
            NODELET_WARN_THROTTLE(5.0, "rgbd registration: %s", s.reason().c_str());
            return;
          }
          {
            std::lock_guard<std::mutex> lock(mutex_);
            if (!live_->Push(std::move(frame))) {
              counts_->Add(kDropped);
              NODELET_WARN_THROTTLE(5.0,
                                    "rgbd registration: too many frames pending; oldest dropped");
            }
            drain();
          }
          stopCameraInfoOnceStarted();
        });
    depth_topic_ = nh.resolveName("depth");
    info_topic_ = nh.resolveName("camera_info");
    info_sub_ = nh.subscribe<Info>("camera_info", 5, [this](const Info::ConstPtr& msg) {
      {
        std::lock_guard<std::mutex> lock(mutex_);
        if (!live_->started()) info_ = msg;
        drain();
      }
      stopCameraInfoOnceStarted();
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
      outputs_->ReleaseIfPaused();
    });
    icgm::nodelets::WarnUnknownParams(getPrivateNodeHandle(), "rgbd registration");
  }

  // The nodelet's callbacks may run on several threads; they share live_ under mutex_.
  void wheelCb(const nav_msgs::Odometry::ConstPtr& msg) {
    std::lock_guard<std::mutex> lock(mutex_);
    if (!live_->AddWheelOdometry(icgm::ros_bridge::FromRos(msg->header.stamp),
                                 icgm::ros_bridge::FromPoseMsg(msg->pose.pose))) {
      NODELET_WARN_THROTTLE(5.0, "rgbd registration: wheel odometry out of order; sample dropped");
      return;
    }
    drain();
  }

  // Whether `depth` has the colour camera's size (its camera_info, once known): depth of another
  // size (not registered to colour, or another camera's camera_info) is refused and counted.
  bool depthFits(const Image& depth) {
    Info::ConstPtr info;
    {
      std::lock_guard<std::mutex> lock(mutex_);
      info = info_;
    }
    if (!info) return true;
    const icgm::Status fits =
        icgm::ros_bridge::CheckImageSize(depth, depth_topic_, *info, info_topic_);
    if (fits.ok()) return true;
    counts_->Add(kRefused);
    NODELET_ERROR_THROTTLE(5.0, "rgbd registration: frame refused: %s", fits.reason().c_str());
    return false;
  }

  // Once the front end started, later camera_info changes nothing: the subscription ends. Called
  // outside mutex_ (shutdown waits for a camera_info callback in progress, which may wait for
  // mutex_); the first caller after the start shuts it down.
  void stopCameraInfoOnceStarted() {
    if (started_ && !info_stopped_.exchange(true)) info_sub_.shutdown();
  }

  void drain() {
    if (!info_) return;  // no camera yet
    if (!live_->started()) {
      if (!icgm::nodelets::StartLiveFrontend(params_.frontend, extrinsic_.get(), *camera_, *info_,
                                             live_.get())) {
        return;
      }
      started_ = true;
    }
    live_->Drain(
        [this](const icgm::LiveFrameOutput& out) {
          outputs_->Publish(out, *live_->frontend(), info_);
          counts_->Add(kProcessed);
        },
        [this](icgm::Time stamp) -> cv::Mat {
          if (!params_.frontend.select_by_evidence) return cv::Mat();
          cv::Mat bgr = images_.Find(icgm::ros_bridge::ToRos(stamp));
          if (bgr.empty()) {
            NODELET_WARN_THROTTLE(10.0,
                                  "rgbd registration: %zu frames without their "
                                  "colour image: motion hypotheses scored on "
                                  "depth alone",
                                  images_.missing());
          }
          return bgr;
        });
  }

  // Subscriptions
  std::unique_ptr<icgm::nodelets::FeaturesDepthSync> sync_;
  ros::Subscriber info_sub_;  // until the front end started
  std::atomic<bool> info_stopped_{false};
  std::string depth_topic_, info_topic_;  // resolved, for the size check's errors
  ros::Subscriber wheel_sub_;
  ros::Subscriber image_sub_;   // with frontend.select_by_evidence
  ros::WallTimer flush_timer_;  // frames whose wheel data never comes; a pause (end of a bag)
  // Publications
  std::unique_ptr<icgm::nodelets::RegistrationOutputs> outputs_;  // relative_pose, keyframes
  ros::Publisher taken_pub_;  // the stamp of every frame taken from the input queues
  // Parameters
  std::unique_ptr<icgm::nodelets::CameraModelReader> camera_;
  icgm::nodelets::RegistrationParams params_;
  std::unique_ptr<icgm::nodelets::ExtrinsicSource> extrinsic_;
  // State
  std::mutex mutex_;
  std::unique_ptr<icgm::LiveFrontend> live_;  // frames waiting for wheel data + the front end
  icgm::nodelets::ImageBuffer images_;        // recent colour images (select_by_evidence)
  std::mutex buffers_mutex_;
  icgm::DepthBuffers depth_buffers_;  // the frames' metric depth, reused once released
  Info::ConstPtr info_;  // the latest camera_info before the start, the front end's after it
  std::atomic<bool> started_{false};  // live_->started(), read outside mutex_
  enum Count : size_t { kPaired, kRefused, kDropped, kProcessed };
  std::unique_ptr<icgm::nodelets::FrameCounts> counts_;
};

}  // namespace icgm_slam

PLUGINLIB_EXPORT_CLASS(icgm_slam::RgbdRegistrationNodelet, nodelet::Nodelet)
