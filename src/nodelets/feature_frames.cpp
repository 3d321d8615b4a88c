#include "nodelets/feature_frames.h"

#include <utility>

#include "ros_bridge/conversions.h"

namespace icgm::nodelets {

FeatureFrames::FeatureFrames(bool track, const TrackerOptions& options) {
  if (track) {
    tracker_ = std::make_unique<RobustFeatureTracker>(options);
  } else {
    extractor_ = FeatureExtractor::Create(options.features);
  }
}

Status FeatureFrames::Read(const sensor_msgs::ImageConstPtr& msg, cv::Mat* bgr) const {
  // Extraction only reads the image: a view of the message's pixels, no copy (the message is
  // kept with it in history_). The tracker keeps images of its own: a copy.
  return tracker_ ? ros_bridge::ColorFromImageMsg(*msg, bgr)
                  : ros_bridge::ColorViewOfImageMsg(*msg, bgr);
}

std::optional<FeatureFrames::Completed> FeatureFrames::Add(const sensor_msgs::ImageConstPtr& msg,
                                                           const cv::Mat& bgr, bool* restarted) {
  const Time stamp = ros_bridge::FromRos(msg->header.stamp);
  *restarted = last_stamp_ && stamp <= *last_stamp_;
  if (*restarted) {
    if (tracker_) tracker_->Reset();
    history_.clear();
  }
  last_stamp_ = stamp;
  history_.push_back({stamp, bgr, msg->header.frame_id, msg});
  if (history_.size() > 3) history_.erase(history_.begin());
  std::optional<TrackedFrame> out;
  if (tracker_) {
    out = tracker_->AddImage(stamp, bgr);
  } else {
    out.emplace();
    out->stamp = stamp;
    out->features = extractor_->Extract(bgr);
  }
  if (!out) return std::nullopt;
  Completed completed;
  completed.frame = std::move(*out);
  // The image and frame id of the completed frame (this or the previous one).
  for (const Stored& h : history_) {
    if (h.stamp != completed.frame.stamp) continue;
    completed.bgr = &h.bgr;
    completed.frame_id = h.frame_id;
  }
  completed.previous = previous_ ? &*previous_ : nullptr;
  return completed;
}

}  // namespace icgm::nodelets
