// RegistrationResult (core) <-> icgm_slam/RegistrationResult (message). Round-trip tested.
#pragma once

#include <icgm_slam/RegistrationResult.h>

#include "core/common/time.h"
#include "core/registration/rgbd_registration.h"

namespace icgm::ros_bridge {

icgm_slam::RegistrationResult ToRegistrationMsg(const RegistrationResult& result, Time stamp,
                                                Time reference_stamp,
                                                const std::string& frame_id);

// Restores status, pose, covariance and counts (inlier indices and depth reject counts are not
// carried by the message).
RegistrationResult FromRegistrationMsg(const icgm_slam::RegistrationResult& msg);

}  // namespace icgm::ros_bridge
