// The sensor calibration a camera_info message does not carry (depth timing, depth correction,
// rolling shutter), read the same way by every nodelet that lifts keypoints with depth.
#pragma once

#include <string>

#include <ros/node_handle.h>

#include "core/common/camera.h"

namespace icgm::nodelets {

// From the private parameters: first ~camera_config_file (a camera YAML such as
// config/camera/tum_fr1.yaml: its depth_time_offset_s, depth_correction, readout_s and
// first_row_offset_s), then the single parameters of those names, which override the file.
// Values are checked by the camera YAML's rules (core/dataset/camera_options.h). A refused file
// or value is skipped and described in *error (empty when all was accepted); the result holds
// everything accepted. Only the sensor calibration fields of the result are meant to be used
// (CopySensorCalibration); intrinsics come from camera_info.
CameraIntrinsics ReadSensorCalibration(const ros::NodeHandle& pnh, std::string* error);

}  // namespace icgm::nodelets
