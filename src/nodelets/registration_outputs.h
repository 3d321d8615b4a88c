// What the registration nodelet makes of each frame its live front end processed
// (core LiveFrameOutput): the relative pose on `relative_pose` (icgm_slam/RegistrationResult,
// a failed registration's frame is logged and left out, as before the fusion sees it), the
// keyframes on `keyframes` (keyframe_outlet.h), the throttled wheel warnings and the CPU report.
#pragma once

#include <memory>

#include <ros/ros.h>
#include <sensor_msgs/CameraInfo.h>

#include "core/slam/live_frontend.h"
#include "nodelets/cpu_meter.h"
#include "nodelets/keyframe_outlet.h"

namespace icgm::nodelets {

class RegistrationOutputs {
 public:
  RegistrationOutputs(ros::NodeHandle& nh, const MapFeatureOptions& map_features,
                      double keyframe_hold_max_s);

  // One processed frame of `frontend`, whose camera is `info`.
  void Publish(const LiveFrameOutput& out, const RgbdFrontend& frontend,
               const sensor_msgs::CameraInfo::ConstPtr& info);
  // A held keyframe leaves when no frame came for ~keyframe_hold_max_s (logged).
  void ReleaseIfPaused();

 private:
  ros::Publisher result_pub_;
  KeyframeOutlet keyframes_;
  CpuMeter cpu_;
};

}  // namespace icgm::nodelets
