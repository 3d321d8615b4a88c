#include "core/dataset/camera_options.h"

namespace icgm {

namespace {
constexpr double kMinPositive = 1e-9;
constexpr double kMaxPixels = 1e5;
}  // namespace

void ReadOptions(const OptionReader& camera_section, CameraIntrinsics* out) {
  camera_section.Read("fx_px", &out->fx_px, kMinPositive, kMaxPixels);
  camera_section.Read("fy_px", &out->fy_px, kMinPositive, kMaxPixels);
  camera_section.Read("cx_px", &out->cx_px, -kMaxPixels, kMaxPixels);
  camera_section.Read("cy_px", &out->cy_px, -kMaxPixels, kMaxPixels);
  camera_section.Read("width_px", &out->width_px, 1, static_cast<int>(kMaxPixels));
  camera_section.Read("height_px", &out->height_px, 1, static_cast<int>(kMaxPixels));
  camera_section.Read("depth_scale", &out->depth_scale, kMinPositive, 1e9);
  camera_section.Read("depth_time_offset_s", &out->depth_time_offset_s, -1.0, 1.0);
  camera_section.Read("depth_correction", &out->depth_correction, kMinDepthCorrection,
                      kMaxDepthCorrection);
  camera_section.Read("readout_s", &out->readout_s, 0.0, 1.0);
  camera_section.Read("first_row_offset_s", &out->first_row_offset_s, -1.0, 1.0);
  camera_section.Read("distortion_k1", &out->distortion_k1, -100.0, 100.0);
  camera_section.Read("distortion_k2", &out->distortion_k2, -100.0, 100.0);
  camera_section.Read("distortion_p1", &out->distortion_p1, -1.0, 1.0);
  camera_section.Read("distortion_p2", &out->distortion_p2, -1.0, 1.0);
  camera_section.Read("distortion_k3", &out->distortion_k3, -100.0, 100.0);
}

void CopySensorCalibration(const CameraIntrinsics& calibration, CameraIntrinsics* intrinsics) {
  intrinsics->depth_time_offset_s = calibration.depth_time_offset_s;
  intrinsics->depth_correction = calibration.depth_correction;
  intrinsics->readout_s = calibration.readout_s;
  intrinsics->first_row_offset_s = calibration.first_row_offset_s;
}

CameraIntrinsics LoadCameraIntrinsics(const std::string& yaml_path) {
  const OptionReader root = OptionReader::FromFile(yaml_path);
  if (!root.Has("camera")) throw LoadError("'" + yaml_path + "' has no 'camera' section");
  const OptionReader section = root.Section("camera");
  for (const char* key : kRequiredCameraKeys) {
    if (!section.Has(key)) {
      throw LoadError("'" + yaml_path + "': required key 'camera." + key + "' missing");
    }
  }
  CameraIntrinsics intrinsics;
  ReadOptions(section, &intrinsics);
  // The depth camera's own section belongs to the depth registration, which checks its keys.
  root.Section("depth_camera");
  for (const OptionReader* reader : {&section, &root}) {
    const auto unused = reader->UnusedKeys();
    if (!unused.empty()) {
      throw LoadError("'" + yaml_path + "': unknown key '" + unused.front() + "'");
    }
  }
  return intrinsics;
}

}  // namespace icgm
