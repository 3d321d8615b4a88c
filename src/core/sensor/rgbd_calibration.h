// What an RGB-D driver publishes with a device's images besides the images: the colour camera's
// intrinsics for camera_info (from a camera YAML's `camera` section, else the device's field of
// view) and, for a device that does not register depth to colour itself, the software
// registration that the YAML's `depth_camera` section allows (depth_registration.h).
#pragma once

#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "core/common/camera.h"
#include "core/sensor/depth_registration.h"

namespace icgm {

struct RgbdCalibration {
  std::optional<CameraIntrinsics> color;               // the YAML's camera section
  std::optional<DepthCameraCalibration> depth_camera;  // its depth_camera section
};

// Reads a camera YAML. A refused section is left out, its reason appended to *problems.
RgbdCalibration LoadRgbdCalibration(const std::string& yaml_path, std::vector<std::string>* problems);

// The registration a device's depth needs: null when the device registers in hardware or no
// depth camera is known (its depth is then published as delivered).
std::shared_ptr<const DepthRegistration> SoftwareRegistration(const RgbdCalibration& calibration,
                                                              bool device_registers,
                                                              const CameraIntrinsics& color);

}  // namespace icgm
