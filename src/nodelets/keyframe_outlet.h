// The registration front end's keyframes on their way to the map (`keyframes`,
// icgm_slam/Keyframe, only while someone listens): the features chosen by map.yaml's
// map_features.source (core MapFeatureTracking). With source tracker a keyframe is held for its
// next frame, as in SlamSystem; it leaves earlier
//  - when the frames pause for `hold_max_s` of wall time (end of a bag): with the backward half
//    of the tracker's window, the tracker's sequence going on (ReleaseIfPaused);
//  - on request, service `<keyframes>/flush` (icgm_slam/FlushKeyframe; KeyframeFlushService: the
//    keyframes topic as resolved, remaps included, so the service goes wherever the keyframes
//    go, e.g. /icgm/keyframes/flush): the map builder's mode switch, as SlamSystem::SetMode
//    flushes; the keyframe comes back in the answer (so it enters the map before the switch)
//    and the tracker starts a new sequence.
// Thread-safe: the service runs on another thread than the frames.
#pragma once

#include <memory>
#include <mutex>
#include <optional>
#include <string>

#include <ros/ros.h>
#include <sensor_msgs/CameraInfo.h>

#include <icgm_slam/FlushKeyframe.h>
#include <icgm_slam/Keyframe.h>

#include "core/odometry/rgbd_frontend.h"
#include "core/slam/map_feature_tracking.h"

namespace icgm::nodelets {

// The flush service of the `keyframes` topic of `nh`: "<resolved keyframes>/flush". The map
// builder (keyframe_intake.h) calls the name its own `keyframes` resolves to, so the two meet
// whatever their namespaces, as long as the topic connects them.
std::string KeyframeFlushService(const ros::NodeHandle& nh);

class KeyframeOutlet {
 public:
  KeyframeOutlet(ros::NodeHandle& nh, const MapFeatureOptions& options, double hold_max_s);

  // After the front end processed a frame of `camera_frame` (whatever its outcome):
  // `new_keyframe` is the keyframe it made during it (nullptr: none).
  void AfterFrame(const RgbdFrontend& frontend, KeyframePtr new_keyframe,
                  const std::string& camera_frame, const sensor_msgs::CameraInfo::ConstPtr& info);
  // Releases a held keyframe when no frame came for hold_max_s; true when one left.
  bool ReleaseIfPaused();
  double hold_max_s() const { return hold_max_s_; }

 private:
  bool Flush(icgm_slam::FlushKeyframe::Request& req, icgm_slam::FlushKeyframe::Response& res);
  icgm_slam::Keyframe::Ptr ToMsg(const FrontendKeyframe& keyframe) const;
  void Publish(const std::optional<FrontendKeyframe>& keyframe);

  std::mutex mutex_;
  ros::Publisher pub_;
  ros::ServiceServer flush_;
  MapFeatureOptions options_;
  MapFeatureTracking tracking_;
  double hold_max_s_;
  std::string camera_frame_;  // of the last frame
  sensor_msgs::CameraInfo::ConstPtr info_;
  ros::WallTime last_frame_wall_;
};

}  // namespace icgm::nodelets
