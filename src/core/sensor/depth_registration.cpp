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
  const Eigen::Matrix3d R = calibration_.T_color_depth.linear();
  for (int u = 0; u <= k.width_px; ++u) {
    column_.push_back(((u - 0.5 - k.cx_px) / k.fx_px * R.col(0)).cast<float>());
  }
  for (int v = 0; v <= k.height_px; ++v) {
    row_.push_back(((v - 0.5 - k.cy_px) / k.fy_px * R.col(1) + R.col(2)).cast<float>());
  }
}

cv::Mat DepthRegistration::Register(const cv::Mat& depth_mm) const {
  const CameraIntrinsics& k = calibration_.depth;
  if (depth_mm.type() != CV_16UC1 || depth_mm.cols != k.width_px || depth_mm.rows != k.height_px) {
    return cv::Mat();
  }
  cv::Mat out(color_.height_px, color_.width_px, CV_16UC1, cv::Scalar(0));
  const Eigen::Vector3f t = calibration_.T_color_depth.translation().cast<float>();
  const float fx = static_cast<float>(color_.fx_px), fy = static_cast<float>(color_.fy_px);
  const float cx = static_cast<float>(color_.cx_px), cy = static_cast<float>(color_.cy_px);
  // A point z * ray of the depth camera is z * (column + row) + t in the colour frame.
  const auto project = [&](float z, const Eigen::Vector3f& ray, float* u, float* v) {
    const Eigen::Vector3f p = z * ray + t;
    if (p.z() <= 1e-6f) return -1.0f;
    const float inv_z = 1.0f / p.z();
    *u = fx * p.x() * inv_z + cx;
    *v = fy * p.y() * inv_z + cy;
    return p.z();
  };
  for (int v = 0; v < depth_mm.rows; ++v) {
    const uint16_t* row = depth_mm.ptr<uint16_t>(v);
    for (int u = 0; u < depth_mm.cols; ++u) {
      if (row[u] == 0) continue;
      const float z = row[u] * 1e-3f;
      // The pixel's footprint: the projections of its top-left and bottom-right corners.
      float u0 = 0.0f, v0 = 0.0f, u1 = 0.0f, v1 = 0.0f;
      const float z0 = project(z, column_[u] + row_[v], &u0, &v0);
      const float z1 = project(z, column_[u + 1] + row_[v + 1], &u1, &v1);
      if (z0 <= 0.0f || z1 <= 0.0f) continue;
      constexpr float kFar = 1e6f;  // far outside the image (and safe to convert to int)
      if (!(std::abs(u0) < kFar && std::abs(u1) < kFar && std::abs(v0) < kFar && std::abs(v1) < kFar)) {
        continue;
      }
      const float mm = std::round(500.0f * (z0 + z1));
      if (mm < 1.0f || mm > std::numeric_limits<uint16_t>::max()) continue;
      const uint16_t value = static_cast<uint16_t>(mm);
      // Colour pixels whose centres lie inside the footprint (at least the nearest one).
      int ua = static_cast<int>(std::ceil(std::min(u0, u1)));
      int ub = static_cast<int>(std::floor(std::max(u0, u1)));
      int va = static_cast<int>(std::ceil(std::min(v0, v1)));
      int vb = static_cast<int>(std::floor(std::max(v0, v1)));
      if (ub < ua) ua = ub = static_cast<int>(std::lround(0.5f * (u0 + u1)));
      if (vb < va) va = vb = static_cast<int>(std::lround(0.5f * (v0 + v1)));
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
