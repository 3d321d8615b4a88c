#include "nodelets/keyframe_outlet.h"

#include <utility>

#include <boost/make_shared.hpp>

#include "ros_bridge/keyframe_msgs.h"

namespace icgm::nodelets {

std::string KeyframeFlushService(const ros::NodeHandle& nh) {
  return nh.resolveName("keyframes") + "/flush";
}

KeyframeOutlet::KeyframeOutlet(ros::NodeHandle& nh, const MapFeatureOptions& options,
                               double hold_max_s)
    : options_(options), tracking_(options), hold_max_s_(hold_max_s) {
  pub_ = nh.advertise<icgm_slam::Keyframe>("keyframes", 20);
  flush_ = nh.advertiseService(KeyframeFlushService(nh), &KeyframeOutlet::Flush, this);
}

void KeyframeOutlet::AfterFrame(const RgbdFrontend& frontend, KeyframePtr new_keyframe,
                                const std::string& camera_frame,
                                const sensor_msgs::CameraInfo::ConstPtr& info) {
  std::lock_guard<std::mutex> lock(mutex_);
  camera_frame_ = camera_frame;
  info_ = info;
  last_frame_wall_ = ros::WallTime::now();
  // The keyframe entering the map now (one frame late with map_features.source tracker).
  Publish(tracking_.AfterFrame(frontend, std::move(new_keyframe)));
}

bool KeyframeOutlet::ReleaseIfPaused() {
  std::lock_guard<std::mutex> lock(mutex_);
  if (!tracking_.holding() ||
      ros::WallTime::now() - last_frame_wall_ < ros::WallDuration(hold_max_s_)) {
    return false;
  }
  Publish(tracking_.ReleaseHeld());
  return true;
}

bool KeyframeOutlet::Flush(icgm_slam::FlushKeyframe::Request&,
                           icgm_slam::FlushKeyframe::Response& res) {
  std::lock_guard<std::mutex> lock(mutex_);
  const std::optional<FrontendKeyframe> keyframe = tracking_.Flush();
  res.held = keyframe.has_value();
  if (keyframe) res.keyframe = *ToMsg(*keyframe);
  return true;
}

icgm_slam::Keyframe::Ptr KeyframeOutlet::ToMsg(const FrontendKeyframe& keyframe) const {
  auto msg = boost::make_shared<icgm_slam::Keyframe>(
      ros_bridge::ToKeyframeMsg(keyframe, camera_frame_, *info_));
  msg->map_features_source = NameOf(options_.source);
  return msg;
}

void KeyframeOutlet::Publish(const std::optional<FrontendKeyframe>& keyframe) {
  if (!keyframe || pub_.getNumSubscribers() == 0) return;
  // A shared pointer: the map builder in the same manager gets it without serialization.
  pub_.publish(ToMsg(*keyframe));
}

}  // namespace icgm::nodelets
