#include "core/sensor/depth_registration.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include <Eigen/Geometry>

namespace icgm {

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

bool LoadDepthCameraCalibration(const std::string& yaml_path, DepthCameraCalibration* out) {
  const OptionReader root = OptionReader::FromFile(yaml_path);
  if (!root.Has("depth_camera")) return false;
  ReadOptions(root.Section("depth_camera"), out);
  return true;
}

DepthRegistration::DepthRegistration(const DepthCameraCalibration& calibration,
                                     const CameraIntrinsics& color)
    : calibration_(calibration), color_(color) {
  const CameraIntrinsics& k = calibration_.depth;
  for (int u = 0; u <= k.width_px; ++u) x_edge_.push_back((u - 0.5 - k.cx_px) / k.fx_px);
  for (int v = 0; v <= k.height_px; ++v) y_edge_.push_back((v - 0.5 - k.cy_px) / k.fy_px);
}

cv::Mat DepthRegistration::Register(const cv::Mat& depth_mm) const {
  const CameraIntrinsics& k = calibration_.depth;
  if (depth_mm.type() != CV_16UC1 || depth_mm.cols != k.width_px || depth_mm.rows != k.height_px) {
    return cv::Mat();
  }
  cv::Mat out(color_.height_px, color_.width_px, CV_16UC1, cv::Scalar(0));
  const Eigen::Matrix3d R = calibration_.T_color_depth.linear();
  const Eigen::Vector3d t = calibration_.T_color_depth.translation();
  // A point z * (x, y, 1) of the depth camera is z * (x R0 + y R1 + R2) + t in the colour frame.
  const auto project = [&](double z, double x, double y, double* u, double* v) {
    const Eigen::Vector3d p = z * (x * R.col(0) + y * R.col(1) + R.col(2)) + t;
    if (p.z() <= 1e-6) return -1.0;
    *u = color_.fx_px * p.x() / p.z() + color_.cx_px;
    *v = color_.fy_px * p.y() / p.z() + color_.cy_px;
    return p.z();
  };
  for (int v = 0; v < depth_mm.rows; ++v) {
    const uint16_t* row = depth_mm.ptr<uint16_t>(v);
    for (int u = 0; u < depth_mm.cols; ++u) {
      if (row[u] == 0) continue;
      const double z = row[u] * 1e-3;
      // The pixel's footprint: the projections of its top-left and bottom-right corners.
      double u0 = 0.0, v0 = 0.0, u1 = 0.0, v1 = 0.0;
      const double z0 = project(z, x_edge_[u], y_edge_[v], &u0, &v0);
      const double z1 = project(z, x_edge_[u + 1], y_edge_[v + 1], &u1, &v1);
      if (z0 <= 0.0 || z1 <= 0.0) continue;
      const double zc = 0.5 * (z0 + z1);
      const double mm = std::round(zc * 1e3);
      if (mm < 1.0 || mm > std::numeric_limits<uint16_t>::max()) continue;
      const uint16_t value = static_cast<uint16_t>(mm);
      // Colour pixels whose centres lie inside the footprint (at least the nearest one).
      int ua = static_cast<int>(std::ceil(std::min(u0, u1)));
      int ub = static_cast<int>(std::floor(std::max(u0, u1)));
      int va = static_cast<int>(std::ceil(std::min(v0, v1)));
      int vb = static_cast<int>(std::floor(std::max(v0, v1)));
      if (ub < ua) ua = ub = static_cast<int>(std::lround(0.5 * (u0 + u1)));
      if (vb < va) va = vb = static_cast<int>(std::lround(0.5 * (v0 + v1)));
      ua = std::max(ua, 0);
      va = std::max(va, 0);
      ub = std::min(ub, out.cols - 1);
      vb = std::min(vb, out.rows - 1);
      for (int y = va; y <= vb; ++y) {
        uint16_t* dst = out.ptr<uint16_t>(y);
        for (int x = ua; x <= ub; ++x) {
          if (dst[x] == 0 || value < dst[x]) dst[x] = value;
        }
      }
    }
  }
  return out;
}

}  // namespace icgm
