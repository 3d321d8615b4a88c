// FrontendKeyframe (core) <-> icgm_slam/Keyframe (message): the registration nodelet's front end
// hands its keyframes to the map builder nodelet, as the offline front end hands them to the
// map. Round-trip tested (poses to rounding, everything else exactly).
#pragma once

#include <string>

#include <icgm_slam/Keyframe.h>
#include <sensor_msgs/CameraInfo.h>

#include "core/common/status.h"
#include "core/odometry/frontend_types.h"

namespace icgm::ros_bridge {

// `frame_id`: the camera optical frame; `camera_info`: the camera the front end was made with.
icgm_slam::Keyframe ToKeyframeMsg(const FrontendKeyframe& keyframe, const std::string& frame_id,
                                  const sensor_msgs::CameraInfo& camera_info);

// Fails on inconsistent sizes (features, robust flags, points) or unreadable images.
Status FromKeyframeMsg(const icgm_slam::Keyframe& msg, FrontendKeyframe* keyframe);

}  // namespace icgm::ros_bridge
