// Camera intrinsics from configuration (config/camera/*.yaml, section `camera:`):
//   camera:
//     fx_px: 517.3
//     fy_px: 516.5
//     cx_px: 318.6
//     cy_px: 255.3
//     width_px: 640
//     height_px: 480
//     depth_scale: 5000.0   # depth image value per metre
//     depth_time_offset_s: 0.0   # optional, see CameraIntrinsics::depth_time_offset_s
//     depth_correction: 1.0      # optional, see CameraIntrinsics::depth_correction
//     readout_s: 0.0             # optional rolling shutter, see CameraIntrinsics::readout_s
//     first_row_offset_s: 0.0    # optional, see CameraIntrinsics::first_row_offset_s
//     distortion_k1: 0.0         # optional, k1 k2 p1 p2 k3 (plumb_bob), see CameraIntrinsics
#pragma once

#include <string>

#include "core/common/camera.h"
#include "core/common/option_reader.h"

namespace icgm {

// The intrinsics a camera file must give: a missing one is an error, never a default.
constexpr const char* kRequiredCameraKeys[] = {"fx_px", "fy_px", "cx_px", "cy_px",
                                               "width_px", "height_px", "depth_scale"};

// Fills `out` from the `camera` section reader (keys absent keep their value, so single
// parameters can be checked through it). Throws LoadError for a wrong type or an out-of-range value (focal lengths and depth_scale must be
// positive, sizes in [1, 100000], principal point within +-100000 px).
void ReadOptions(const OptionReader& camera_section, CameraIntrinsics* out);

// Depth corrections accepted (also from node parameters, which go through ReadOptions): a
// sensor whose depth is off by more than a factor of two is miscalibrated, not in need of a
// correction.
constexpr double kMinDepthCorrection = 0.5;
constexpr double kMaxDepthCorrection = 2.0;

// The sensor calibration a ROS camera_info does not carry (depth timing and scale, rolling
// shutter), copied from `calibration` (e.g. a camera YAML) into `intrinsics`.
void CopySensorCalibration(const CameraIntrinsics& calibration, CameraIntrinsics* intrinsics);

// Reads the `camera` section of a YAML file. Throws LoadError when the file is unreadable,
// has no `camera` section, lacks a required key (kRequiredCameraKeys) or has unknown keys (in
// `camera`, or at the top level, where `depth_camera` is the only other section).
CameraIntrinsics LoadCameraIntrinsics(const std::string& yaml_path);

}  // namespace icgm
