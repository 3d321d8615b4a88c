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
#include "core/common/status.h"
#include "core/sensor/depth_registration.h"

namespace icgm {

struct RgbdCalibration {
  std::optional<CameraIntrinsics> color;               // the YAML's camera section
  std::optional<DepthCameraCalibration> depth_camera;  // its depth_camera section
};

// Reads a camera YAML. An invalid file (in any section) gives neither calibration; its reason is
// appended to *problems.
RgbdCalibration LoadRgbdCalibration(const std::string& yaml_path, std::vector<std::string>* problems);

// Whether `calibration`'s colour camera (from `yaml_path`) was calibrated for the image size the
// device streams: intrinsics of another size would be published as its camera_info and every
// pixel back-projected with the wrong focal length. No colour calibration fits any size.
Status CheckCalibratedSize(const RgbdCalibration& calibration, int width_px, int height_px,
                           const std::string& yaml_path);

// The registration a device's depth needs: null when the device registers in hardware or no
// depth camera is known (its depth is then published as delivered).
std::shared_ptr<const DepthRegistration> SoftwareRegistration(const RgbdCalibration& calibration,
                                                              bool device_registers,
                                                              const CameraIntrinsics& color);

}  // namespace icgm
