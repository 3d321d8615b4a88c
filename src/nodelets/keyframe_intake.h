// Keyframes of the registration nodelet entering the running map (core LiveMap): their
// features must follow this map's map_features.source (never a silent difference); the map
// starts with the first keyframe's camera (loading ~load_map then); each keyframe waits for the
// fused odometry at its stamp (odometry_wait.h), takes its pose from it and goes to the map; the
// outcome (loop closed, localized, autosave) is logged and handed to `added`. A keyframe whose
// depth or colour image has another size than the map's camera is refused (throttled error with
// both sizes, the topic and the count so far); the map keeps what it has.
// Before a mode switch the registration's held keyframe is asked for (`<keyframes>/flush`,
// keyframe_outlet.h) and the waiting keyframes enter (bounded wait for their odometry), so they
// enter the map in the mode they were made in, as SlamSystem::SetMode flushes offline.
#pragma once

#include <cstddef>
#include <functional>
#include <memory>
#include <string>

#include <ros/ros.h>
#include <tf2_ros/buffer.h>

#include <icgm_slam/Keyframe.h>

#include "core/slam/live_map.h"
#include "nodelets/nodelet_params.h"
#include "nodelets/odometry_wait.h"

namespace icgm::nodelets {

class KeyframeIntake {
 public:
  struct Callbacks {
    std::function<void()> loaded;                     // a map was loaded at the start
    std::function<void(const LiveMapUpdate&)> added;  // a keyframe entered the map
  };
  // `map`, `camera` and `tf` outlive this object. ~tf_wait_s: the odometry wait.
  KeyframeIntake(ros::NodeHandle& nh, const ros::NodeHandle& pnh, LiveMap* map,
                 const CameraModelReader* camera, const tf2_ros::Buffer& tf,
                 const std::string& odom_frame, std::string map_features_source,
                 Callbacks callbacks);

  void Add(const icgm_slam::Keyframe& msg);
  void Drain();  // keyframes whose odometry came since
  void FlushBeforeModeSwitch();
  const std::string& camera_frame() const { return camera_frame_; }  // empty before a keyframe

 private:
  bool Start(const sensor_msgs::CameraInfo& info);
  // Whether the keyframe's images have the size of the map's camera (logged when not).
  bool Fits(const icgm_slam::Keyframe& msg);
  void Process(const FrontendKeyframe& keyframe);

  LiveMap* map_;
  const CameraModelReader* camera_;
  std::string map_features_source_;
  Callbacks callbacks_;
  double tf_wait_s_;
  std::unique_ptr<OdometryWait> waiting_;
  ros::ServiceClient flush_;
  std::string camera_frame_;
  std::string keyframes_topic_;            // resolved, for the size check's errors
  sensor_msgs::CameraInfo camera_info_;    // the map's camera: the first keyframe's
  size_t refused_ = 0;                     // keyframes of another size
};

}  // namespace icgm::nodelets
