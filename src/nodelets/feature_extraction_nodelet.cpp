// Feature extraction nodelet: RGB image -> ICGM robust features (icgm_slam/RobustFeatures) and a
// debug overlay (thesis Fig. 6.4) built only while someone subscribes. Double-directional mode
// publishes each frame one frame late (it needs I(t+1)).
// Features are extracted on the image with camera_info's lens distortion undone, as the offline
// front end extracts them (core LensUndistortion); images wait for the first camera_info up to
// ~camera_info_wait_s, after which features come from the raw image (flagged in the message,
// the consumers then move the keypoints). Once fixed, camera_info is no longer subscribed.
// ~track (default false): the robust flags and matches of ICGM between consecutive frames
// (~mode, thesis ch. 4.1.3-4.1.5), shown by the debug overlay. false: features only (flags all
// false, no matches, no delay): the registration matches each frame to its keyframe itself and
// the map takes its keyframes' flags from there, so the pipeline does not need the tracks.
// Backpressure (core InFlightLimit): once the registration announces the frames it takes from its
// input queues (`taken_frames`, std_msgs/Header), an image is skipped, not extracted, while
// ~max_frames_in_flight (default 5; 0: never skip) extracted frames are still waiting there, so no
// CPU goes to features the registration's queues would drop. ~in_flight_stall_s (1.0): wall time
// without an answer after which that count starts again. Images received, skipped and extracted are
// counted on /diagnostics (frame_counts.h), and images refused: of another size than the
// camera_info that fixed the undistortion (a throttled error names both sizes and the topic).
#include <atomic>
#include <memory>
#include <mutex>
#include <optional>
#include <string>

#include <image_transport/image_transport.h>
#include <nodelet/nodelet.h>
#include <ros/ros.h>
#include <sensor_msgs/CameraInfo.h>
#include <std_msgs/Header.h>
#include <boost/make_shared.hpp>
#include <pluginlib/class_list_macros.hpp>

#include "core/common/option_reader.h"
#include "core/icgm/robust_feature_tracker.h"
#include "core/slam/in_flight_limit.h"
#include "core/viz/feature_overlay.h"
#include "nodelets/cpu_meter.h"
#include "nodelets/feature_frames.h"
#include "nodelets/frame_counts.h"
#include "nodelets/nodelet_params.h"
#include "nodelets/undistortion_gate.h"
#include "ros_bridge/conversions.h"
#include "ros_bridge/feature_msgs.h"
#include "ros_bridge/image_size.h"

namespace icgm_slam {

class FeatureExtractionNodelet : public nodelet::Nodelet {
 private:
  void onInit() override {
    namespace nodelets = icgm::nodelets;
    ros::NodeHandle& nh = getNodeHandle();
    ros::NodeHandle& pnh = getPrivateNodeHandle();
    // Parameters
    const int queue_size = nodelets::Param(pnh, "queue_size", 5);
    gate_ = std::make_unique<nodelets::UndistortionGate>(
        nodelets::Param(pnh, "camera_info_wait_s", 2.0));
    const bool track = nodelets::Param(pnh, "track", false);  // ICGM only for the debug image
    icgm::TrackerOptions options;
    icgm::InFlightLimitOptions in_flight;
    nodelets::ApplyOpenCvThreads(pnh, "feature extraction");
    nodelets::LoadConfiguration("feature extraction", [&] {
      const std::string config_file = nodelets::Param(pnh, "config_file", "");
      if (!config_file.empty()) {
        icgm::ReadOptions(icgm::OptionReader::FromFile(config_file), &options);
      }
      std::string mode;
      if (nodelets::GetParam(pnh, "mode", &mode)) {
        const std::optional<icgm::TrackerMode> parsed = icgm::ParseEnum<icgm::TrackerMode>(mode);
        if (!parsed) throw icgm::LoadError("~mode: " + icgm::NotOneOf<icgm::TrackerMode>(mode));
        options.mode = *parsed;
      }
      in_flight.max_frames = nodelets::Param(pnh, "max_frames_in_flight", in_flight.max_frames);
      in_flight.stall_s = nodelets::Param(pnh, "in_flight_stall_s", in_flight.stall_s);
      if (icgm::Status s = icgm::Validate(in_flight); !s.ok()) {
        throw icgm::LoadError("~max_frames_in_flight / ~in_flight_stall_s: " + s.reason());
      }
    });
    limit_ = std::make_unique<icgm::InFlightLimit>(in_flight);
    frames_ = std::make_unique<nodelets::FeatureFrames>(track, options);
    if (track) {
      NODELET_INFO("feature extraction: %s ICGM, window %d, detector %s, Thr %.3f",
                   icgm::NameOf(options.mode), options.window_size,
                   icgm::NameOf(options.features.detector), options.icgm.threshold);
    } else {
      NODELET_INFO("feature extraction: detector %s, no tracking between frames",
                   icgm::NameOf(options.features.detector));
    }
    if (in_flight.max_frames > 0) {
      NODELET_INFO(
          "feature extraction: images skipped while %d extracted frames wait for the "
          "registration's answer",
          in_flight.max_frames);
    }
    // Publications
    it_ = std::make_unique<image_transport::ImageTransport>(nh);
    features_pub_ = nh.advertise<icgm_slam::RobustFeatures>("features", 10);
    debug_pub_ = it_->advertise("features/debug_image", 1);
    counts_ = std::make_unique<nodelets::FrameCounts>(
        nh, getName(), std::vector<std::string>{"images", "skipped", "extracted", "refused"});
    // Subscriptions (eager: the tracker keeps state between frames)
    // camera_info first: an image callback may stop it once the undistortion is fixed.
    info_sub_ = nh.subscribe("camera_info", 5, &FeatureExtractionNodelet::infoCb, this);
    info_topic_ = info_sub_.getTopic();
    image_topic_ = nh.resolveName("image");
    image_sub_ = it_->subscribe("image", queue_size, &FeatureExtractionNodelet::imageCb, this);
    if (in_flight.max_frames > 0) {
      processed_sub_ = nh.subscribe<std_msgs::Header>(
          "taken_frames", 10, [this](const std_msgs::Header::ConstPtr& msg) {
            std::lock_guard<std::mutex> lock(mutex_);
            limit_->Answered(icgm::ros_bridge::FromRos(msg->stamp));
          });
    }
    icgm::nodelets::WarnUnknownParams(getPrivateNodeHandle(), "feature extraction");
  }

  // The first valid camera_info fixes the undistortion.
  void infoCb(const sensor_msgs::CameraInfoConstPtr& msg) {
    {
      std::lock_guard<std::mutex> lock(mutex_);
      bool fixed = false;
      if (icgm::Status s = gate_->SetCameraInfo(*msg, &fixed); !s.ok()) {
        NODELET_WARN_THROTTLE(5.0, "feature extraction: bad camera_info: %s", s.reason().c_str());
        return;
      }
      if (fixed) {
        NODELET_INFO("feature extraction: %s", gate_->undistortion()->active()
                                                   ? "lens distortion undone before extraction"
                                                   : "pinhole camera_info, no distortion");
        for (const sensor_msgs::ImageConstPtr& image : gate_->TakeWaiting()) process(image);
      }
      if (gate_->undistortion() == nullptr) return;
    }
    stopCameraInfo();
  }

  void imageCb(const sensor_msgs::ImageConstPtr& msg) {
    {
      std::lock_guard<std::mutex> lock(mutex_);
      counts_->Add(kImages);
      std::string note;
      const std::vector<sensor_msgs::ImageConstPtr> ready = gate_->Add(msg, &note);
      if (!note.empty()) NODELET_WARN_THROTTLE(5.0, "feature extraction: %s", note.c_str());
      for (const sensor_msgs::ImageConstPtr& image : ready) process(image);
      if (info_stopped_ || gate_->undistortion() == nullptr) return;
    }
    stopCameraInfo();
  }

  // Once the undistortion is fixed (by camera_info, or as none after the wait) later
  // camera_info messages change nothing: no callback per frame for them. Called outside mutex_
  // once it is fixed (shutdown waits for a camera_info callback in progress, which may wait for
  // mutex_); the first caller shuts the subscription down.
  void stopCameraInfo() {
    if (!info_stopped_.exchange(true)) info_sub_.shutdown();
  }

  void process(const sensor_msgs::ImageConstPtr& msg) {
    if (const std::optional<icgm::CameraIntrinsics>& k = gate_->camera()) {
      const icgm::Status fits =
          icgm::ros_bridge::CheckImageSize(*msg, image_topic_, *k, info_topic_);
      if (!fits.ok()) {
        counts_->Add(kRefused);
        NODELET_ERROR_THROTTLE(5.0, "feature extraction: image refused: %s", fits.reason().c_str());
        return;
      }
    }
    if (!limit_->Admit(icgm::ros_bridge::FromRos(msg->header.stamp))) {
      counts_->Add(kSkipped);
      return;
    }
    cpu_.Start();
    track(msg);
    if (double ms; cpu_.Stop(&ms)) {
      NODELET_INFO("feature extraction: %.1f ms CPU per frame (last 100)", ms);
    }
  }

  void track(const sensor_msgs::ImageConstPtr& msg) {
    cv::Mat bgr;
    if (icgm::Status s = frames_->Read(msg, &bgr); !s.ok()) {
      NODELET_WARN_THROTTLE(5.0, "feature extraction: dropped image: %s", s.reason().c_str());
      return;
    }
    const std::optional<icgm::Time> last = frames_->last_stamp();
    bool restarted = false;
    std::optional<icgm::nodelets::FeatureFrames::Completed> out =
        frames_->Add(msg, gate_->undistortion()->Colour(bgr), &restarted);
    if (restarted) {
      NODELET_WARN("feature extraction: time went backwards (%s after %s); restarting tracks",
                   icgm::ros_bridge::FromRos(msg->header.stamp).ToString().c_str(),
                   last->ToString().c_str());
    }
    if (!out) return;
    const icgm::TrackedFrame& frame = out->frame;
    const icgm::Time reference = out->previous ? out->previous->stamp : icgm::Time();
    // Published as a shared pointer: nodelets in the same manager get it without serialization.
    icgm_slam::RobustFeatures::Ptr features =
        boost::make_shared<icgm_slam::RobustFeatures>(icgm::ros_bridge::ToFeaturesMsg(
            frame, reference, out->frame_id, frame.icgm_threshold_used));
    features->keypoints_undistorted = gate_->undistortion()->active();
    features_pub_.publish(features);
    counts_->Add(kExtracted);
    if (out->bgr && debug_pub_.getNumSubscribers() > 0) {
      const cv::Mat overlay = icgm::DrawFeatureOverlay(*out->bgr, frame, out->previous);
      debug_pub_.publish(icgm::ros_bridge::ToImageMsg(overlay, "bgr8", out->frame_id, frame.stamp));
    }
    frames_->Published(std::move(out->frame));
  }

  // Subscriptions
  std::unique_ptr<image_transport::ImageTransport> it_;
  image_transport::Subscriber image_sub_;
  ros::Subscriber info_sub_;
  std::atomic<bool> info_stopped_{false};  // info_sub_ shut down (undistortion fixed)
  std::string image_topic_, info_topic_;    // resolved, for the size check's errors
  ros::Subscriber processed_sub_;  // the frames the registration has taken (backpressure)
  // Publications
  ros::Publisher features_pub_;
  image_transport::Publisher debug_pub_;
  // State
  std::mutex mutex_;  // image and camera_info callbacks may run on different threads
  std::unique_ptr<icgm::nodelets::UndistortionGate> gate_;  // images before the camera's lens
  std::unique_ptr<icgm::nodelets::FeatureFrames> frames_;   // extraction or ~track
  std::unique_ptr<icgm::InFlightLimit> limit_;              // extracted frames not yet registered
  icgm::nodelets::CpuMeter cpu_;
  enum Count : size_t { kImages, kSkipped, kExtracted, kRefused };
  std::unique_ptr<icgm::nodelets::FrameCounts> counts_;
};

}  // namespace icgm_slam

PLUGINLIB_EXPORT_CLASS(icgm_slam::FeatureExtractionNodelet, nodelet::Nodelet)
