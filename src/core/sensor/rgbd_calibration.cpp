#include "core/sensor/rgbd_calibration.h"

#include "core/common/image_size.h"
#include "core/dataset/camera_options.h"

namespace icgm {

RgbdCalibration LoadRgbdCalibration(const std::string& yaml_path, std::vector<std::string>* problems) {
  RgbdCalibration out;
  try {
    out.color = LoadCameraIntrinsics(yaml_path);
  } catch (const LoadError& e) {
    // The file is invalid (in either section): neither calibration is taken from it.
    problems->push_back(std::string(e.what()) +
                        "; camera_info from the device's field of view, no software depth "
                        "registration");
    return out;
  }
  try {
    DepthCameraCalibration depth_camera;
    if (LoadDepthCameraCalibration(yaml_path, &depth_camera)) out.depth_camera = depth_camera;
  } catch (const LoadError& e) {
    problems->push_back(std::string(e.what()) + "; no software depth registration");
  }
  return out;
}

Status CheckCalibratedSize(const RgbdCalibration& calibration, int width_px, int height_px,
                           const std::string& yaml_path) {
  if (!calibration.color) return Status::Ok();
  const Status fits =
      CheckImageSize(*calibration.color, yaml_path, width_px, height_px, "the device streams");
  if (fits.ok()) return fits;
  return Status::Error(fits.reason() +
                       ": give ~width_px/~height_px of the calibration or a calibration of " +
                       "this size");
}

std::shared_ptr<const DepthRegistration> SoftwareRegistration(const RgbdCalibration& calibration,
                                                              bool device_registers,
                                                              const CameraIntrinsics& color) {
  if (device_registers || !calibration.depth_camera) return nullptr;
  return std::make_shared<const DepthRegistration>(*calibration.depth_camera, color);
}

}  // namespace icgm
