// TrackedFrame (core) <-> icgm_slam/RobustFeatures (message). Round-trip tested.
#pragma once

#include <icgm_slam/RobustFeatures.h>

#include "core/common/status.h"
#include "core/icgm/robust_feature_tracker.h"

namespace icgm::ros_bridge {

icgm_slam::RobustFeatures ToFeaturesMsg(const TrackedFrame& frame, Time reference_stamp,
                                        const std::string& frame_id, double icgm_threshold);

// Fails on inconsistent sizes (descriptor bytes vs keypoints, match indices out of range).
Status FromFeaturesMsg(const icgm_slam::RobustFeatures& msg, TrackedFrame* frame);

}  // namespace icgm::ros_bridge
