// Feature extraction nodelet: RGB image -> ICGM robust features (icgm_slam/RobustFeatures) and a
// debug overlay (thesis Fig. 6.4) built only while someone subscribes. Double-directional mode
// publishes each frame one frame late (it needs I(t+1)).
#include <memory>
#include <optional>

#include <image_transport/image_transport.h>
#include <nodelet/nodelet.h>
#include <ros/ros.h>
#include <boost/make_shared.hpp>
#include <pluginlib/class_list_macros.hpp>

#include "core/common/option_reader.h"
#include "core/icgm/robust_feature_tracker.h"
#include "core/viz/feature_overlay.h"
#include "nodelets/cpu_meter.h"
#include "ros_bridge/conversions.h"
#include "ros_bridge/feature_msgs.h"

namespace icgm_slam {

class FeatureExtractionNodelet : public nodelet::Nodelet {
 private:
  void onInit() override {
    ros::NodeHandle& nh = getNodeHandle();
    ros::NodeHandle& pnh = getPrivateNodeHandle();
    // Parameters
    std::string config_file;
    pnh.param<std::string>("config_file", config_file, "");
    pnh.param("queue_size", queue_size_, 5);
    icgm::TrackerOptions options;
    try {
      if (!config_file.empty()) {
        icgm::ReadOptions(icgm::OptionReader::FromFile(config_file), &options);
      }
      std::string mode;
      if (pnh.getParam("mode", mode)) {
        const std::optional<icgm::TrackerMode> parsed = icgm::ParseEnum<icgm::TrackerMode>(mode);
        if (!parsed) throw icgm::LoadError("~mode: " + icgm::NotOneOf<icgm::TrackerMode>(mode));
        options.mode = *parsed;
      }
    } catch (const icgm::LoadError& e) {
      NODELET_FATAL("feature extraction: bad configuration: %s", e.what());
      throw;
    }
    threshold_ = options.icgm.threshold;
    tracker_ = std::make_unique<icgm::RobustFeatureTracker>(options);
    NODELET_INFO("feature extraction: %s ICGM, window %d, detector %s, Thr %.3f",
                 icgm::NameOf(options.mode), options.window_size,
                 icgm::NameOf(options.features.detector), threshold_);

    // Publications
    it_ = std::make_unique<image_transport::ImageTransport>(nh);
    features_pub_ = nh.advertise<icgm_slam::RobustFeatures>("features", 10);
    debug_pub_ = it_->advertise("features/debug_image", 1);
    // Subscriptions (eager: the tracker keeps state between frames)
    image_sub_ = it_->subscribe("image", queue_size_, &FeatureExtractionNodelet::imageCb, this);
  }

  void imageCb(const sensor_msgs::ImageConstPtr& msg) {
    cpu_.Start();
    track(msg);
    if (double ms; cpu_.Stop(&ms)) {
      NODELET_INFO("feature extraction: %.1f ms CPU per frame (last 100)", ms);
    }
  }

  void track(const sensor_msgs::ImageConstPtr& msg) {
    cv::Mat bgr;
    if (icgm::Status s = icgm::ros_bridge::ColorFromImageMsg(*msg, &bgr); !s.ok()) {
      NODELET_WARN_THROTTLE(5.0, "feature extraction: dropped image: %s", s.reason().c_str());
      return;
    }
    const icgm::Time stamp = icgm::ros_bridge::FromRos(msg->header.stamp);
    if (last_stamp_ && stamp <= *last_stamp_) {
      NODELET_WARN("feature extraction: time went backwards (%s after %s); restarting tracks",
                   stamp.ToString().c_str(), last_stamp_->ToString().c_str());
      tracker_->Reset();
      history_.clear();
    }
    last_stamp_ = stamp;
    history_.push_back({stamp, bgr, msg->header.frame_id});
    if (history_.size() > 3) history_.erase(history_.begin());
    std::optional<icgm::TrackedFrame> out = tracker_->AddImage(stamp, bgr);
    if (out) publish(*out);
  }

  void publish(const icgm::TrackedFrame& frame) {
    // Find the image and frame id of the completed frame (this or the previous one).
    const Stored* img = nullptr;
    for (const auto& h : history_) {
      if (h.stamp == frame.stamp) img = &h;
    }
    const std::string frame_id = img ? img->frame_id : std::string();
    const icgm::Time reference = previous_ ? previous_->stamp : icgm::Time();
    // Published as a shared pointer: nodelets in the same manager get it without serialization.
    features_pub_.publish(boost::make_shared<icgm_slam::RobustFeatures>(
        icgm::ros_bridge::ToFeaturesMsg(frame, reference, frame_id, frame.icgm_threshold_used)));
    if (img && debug_pub_.getNumSubscribers() > 0) {
      const cv::Mat overlay =
          icgm::DrawFeatureOverlay(img->bgr, frame, previous_ ? &*previous_ : nullptr);
      debug_pub_.publish(icgm::ros_bridge::ToImageMsg(overlay, "bgr8", frame_id, frame.stamp));
    }
    previous_ = frame;
  }

  struct Stored {
    icgm::Time stamp;
    cv::Mat bgr;
    std::string frame_id;
  };

  // Subscriptions
  std::unique_ptr<image_transport::ImageTransport> it_;
  image_transport::Subscriber image_sub_;
  // Publications
  ros::Publisher features_pub_;
  image_transport::Publisher debug_pub_;
  // Parameters
  int queue_size_ = 5;
  double threshold_ = 0.0;
  // State
  std::unique_ptr<icgm::RobustFeatureTracker> tracker_;
  icgm::nodelets::CpuMeter cpu_;
  std::vector<Stored> history_;
  std::optional<icgm::TrackedFrame> previous_;
  std::optional<icgm::Time> last_stamp_;
};

}  // namespace icgm_slam

PLUGINLIB_EXPORT_CLASS(icgm_slam::FeatureExtractionNodelet, nodelet::Nodelet)
