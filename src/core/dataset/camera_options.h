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
#include "core/common/pose.h"

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

// The depth (IR) camera of a device that cannot register depth to colour in hardware, for the
// software registration (core/sensor/depth_registration.h).
// From the optional `depth_camera` section of a camera YAML (the `camera` section
// is the colour camera):
//   depth_camera:
//     fx_px: 575.8         # depth camera pinhole, all six required
//     fy_px: 575.8
//     cx_px: 319.5
//     cy_px: 239.5
//     width_px: 640
//     height_px: 480
//     x_m: -0.025          # the depth camera's pose in the colour camera's optical frame
//     y_m: 0.0             # (x right, y down, z forward); optional, 0 by default
//     z_m: 0.0
//     roll_deg: 0.0        # rotation R = Rz(yaw) Ry(pitch) Rx(roll) about the colour frame's axes
//     pitch_deg: 0.0
//     yaw_deg: 0.0
struct DepthCameraCalibration {
  CameraIntrinsics depth;                    // the depth camera (only the pinhole and size used)
  Pose3 T_color_depth = Pose3::Identity();   // depth camera frame -> colour camera frame
};

// Fills `out` from a `depth_camera` section; throws LoadError for a missing intrinsic, a value out
// of range or an unknown key.
void ReadOptions(const OptionReader& depth_camera_section, DepthCameraCalibration* out);

// Reads the `camera` section of a YAML file. Throws LoadError when the file is unreadable,
// has no `camera` section, lacks a required key (kRequiredCameraKeys) or has unknown keys (in
// `camera`, or at the top level, where `depth_camera` is the only other section). A
// `depth_camera` section is validated too (ReadOptions above), so every reader of a camera file
// refuses a typo anywhere in it, not only the readers that use the depth camera.
CameraIntrinsics LoadCameraIntrinsics(const std::string& yaml_path);

}  // namespace icgm
