#include "nodelets/registration_outputs.h"

#include <boost/make_shared.hpp>

#include <icgm_slam/RegistrationResult.h>

#include "ros_bridge/registration_msgs.h"

namespace icgm::nodelets {

RegistrationOutputs::RegistrationOutputs(ros::NodeHandle& nh, const MapFeatureOptions& map_features,
                                         double keyframe_hold_max_s)
    : result_pub_(nh.advertise<icgm_slam::RegistrationResult>("relative_pose", 20)),
      keyframes_(nh, map_features, keyframe_hold_max_s) {}

void RegistrationOutputs::Publish(const LiveFrameOutput& out, const RgbdFrontend& frontend,
                                  const sensor_msgs::CameraInfo::ConstPtr& info) {
  if (out.missing_wheels) {
    ROS_WARN_THROTTLE(10.0,
                      "rgbd registration: no wheel odometry received; registering without "
                      "the wheel motion prior (set ~camera_only for a camera without "
                      "wheels)");
  }
  if (!out.wheel_status.ok()) {
    ROS_WARN_THROTTLE(5.0, "rgbd registration: wheel odometry: %s",
                      out.wheel_status.reason().c_str());
  }
  if (double ms; cpu_.Add(out.thread_cpu_ms, &ms)) {
    ROS_INFO("rgbd registration: %.1f ms CPU per frame (last 100)", ms);
  }
  keyframes_.AfterFrame(frontend, out.new_keyframe, out.frame->camera_frame, info);
  if (!out.result.status.ok()) {
    ROS_WARN_THROTTLE(5.0, "rgbd registration: frame dropped: %s",
                      out.result.status.reason().c_str());
    return;
  }
  if (!out.step) return;  // the first frame: nothing to register it to
  // A shared pointer: the fusion nodelet in the same manager gets it without serialization.
  result_pub_.publish(
      boost::make_shared<icgm_slam::RegistrationResult>(ros_bridge::ToRegistrationMsg(
          out.step->result, out.step->stamp, out.step->reference_stamp, out.frame->camera_frame)));
}

void RegistrationOutputs::ReleaseIfPaused() {
  if (keyframes_.ReleaseIfPaused()) {
    ROS_INFO(
        "rgbd registration: no frame for %.1f s: the held keyframe goes to the map with the "
        "backward half of its window",
        keyframes_.hold_max_s());
  }
}

}  // namespace icgm::nodelets
