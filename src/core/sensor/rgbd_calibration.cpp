#include "core/sensor/rgbd_calibration.h"

#include "core/dataset/camera_options.h"

namespace icgm {

RgbdCalibration LoadRgbdCalibration(const std::string& yaml_path, std::vector<std::string>* problems) {
  RgbdCalibration out;
  try {
    out.color = LoadCameraIntrinsics(yaml_path);
  } catch (const LoadError& e) {
    problems->push_back(std::string(e.what()) + "; camera_info from the device's field of view");
  }
  try {
    DepthCameraCalibration depth_camera;
    if (LoadDepthCameraCalibration(yaml_path, &depth_camera)) out.depth_camera = depth_camera;
  } catch (const LoadError& e) {
    problems->push_back(std::string(e.what()) + "; no software depth registration");
  }
  return out;
}

std::shared_ptr<const DepthRegistration> SoftwareRegistration(const RgbdCalibration& calibration,
                                                              bool device_registers,
                                                              const CameraIntrinsics& color) {
  if (device_registers || !calibration.depth_camera) return nullptr;
  return std::make_shared<const DepthRegistration>(*calibration.depth_camera, color);
}

}  // namespace icgm
