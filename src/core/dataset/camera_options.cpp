#include "core/dataset/camera_options.h"

#include <cmath>

#include <Eigen/Geometry>

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

void ReadOptions(const OptionReader& r, DepthCameraCalibration* out) {
  for (const char* key : {"fx_px", "fy_px", "cx_px", "cy_px", "width_px", "height_px"}) {
    if (!r.Has(key)) throw LoadError(r.path() + "." + key + ": required");
  }
  CameraIntrinsics& k = out->depth;
  r.Read("fx_px", &k.fx_px, 1.0, 1e5);
  r.Read("fy_px", &k.fy_px, 1.0, 1e5);
  r.Read("cx_px", &k.cx_px, -1e5, 1e5);
  r.Read("cy_px", &k.cy_px, -1e5, 1e5);
  r.Read("width_px", &k.width_px, 1, 100000);
  r.Read("height_px", &k.height_px, 1, 100000);
  k.depth_scale = 1000.0;
  double x_m = 0.0, y_m = 0.0, z_m = 0.0, roll_deg = 0.0, pitch_deg = 0.0, yaw_deg = 0.0;
  r.Read("x_m", &x_m, -1.0, 1.0);
  r.Read("y_m", &y_m, -1.0, 1.0);
  r.Read("z_m", &z_m, -1.0, 1.0);
  r.Read("roll_deg", &roll_deg, -180.0, 180.0);
  r.Read("pitch_deg", &pitch_deg, -180.0, 180.0);
  r.Read("yaw_deg", &yaw_deg, -180.0, 180.0);
  r.RejectUnknownKeys();
  constexpr double kDeg = M_PI / 180.0;
  out->T_color_depth = Pose3::Identity();
  out->T_color_depth.linear() = (Eigen::AngleAxisd(yaw_deg * kDeg, Eigen::Vector3d::UnitZ()) *
                                 Eigen::AngleAxisd(pitch_deg * kDeg, Eigen::Vector3d::UnitY()) *
                                 Eigen::AngleAxisd(roll_deg * kDeg, Eigen::Vector3d::UnitX()))
                                    .toRotationMatrix();
  out->T_color_depth.translation() = Eigen::Vector3d(x_m, y_m, z_m);
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
  if (root.Has("depth_camera")) {
    DepthCameraCalibration depth_camera;
    try {
      ReadOptions(root.Section("depth_camera"), &depth_camera);
    } catch (const LoadError& e) {
      throw LoadError("'" + yaml_path + "': " + e.what());
    }
  }
  for (const OptionReader* reader : {&section, &root}) {
    const auto unused = reader->UnusedKeys();
    if (!unused.empty()) {
      throw LoadError("'" + yaml_path + "': unknown key '" + unused.front() + "'");
    }
  }
  return intrinsics;
}

}  // namespace icgm
