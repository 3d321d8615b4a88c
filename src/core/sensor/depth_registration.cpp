#include "core/sensor/depth_registration.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include <Eigen/Geometry>

namespace icgm {

bool LoadDepthCameraCalibration(const std::string& yaml_path, DepthCameraCalibration* out) {
  LoadCameraIntrinsics(yaml_path);  // the whole file is valid, not only this section
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
    const Eigen::Vector3f c = ((u - 0.5 - k.cx_px) / k.fx_px * R.col(0)).cast<float>();
    column_x_.push_back(c.x());
    column_y_.push_back(c.y());
    column_z_.push_back(c.z());
  }
  for (int v = 0; v <= k.height_px; ++v) {
    const Eigen::Vector3f r = ((v - 0.5 - k.cy_px) / k.fy_px * R.col(1) + R.col(2)).cast<float>();
    row_x_.push_back(r.x());
    row_y_.push_back(r.y());
    row_z_.push_back(r.z());
  }
}

namespace {

// floor, ceil and round-half-away-from-zero of a float of magnitude below 2^23, as integers
// (equal to std::floor, std::ceil and std::lround there, without their library calls).
inline int FloorInt(float x) {
  const int i = static_cast<int>(x);
  return i - (x < static_cast<float>(i));
}
inline int CeilInt(float x) {
  const int i = static_cast<int>(x);
  return i + (x > static_cast<float>(i));
}
inline int RoundInt(float x) {
  const int i = static_cast<int>(x);  // toward zero
  const float frac = x - static_cast<float>(i);  // exact at this magnitude
  return i + (frac >= 0.5f) - (frac <= -0.5f);
}

}  // namespace

cv::Mat DepthRegistration::Register(const cv::Mat& depth_mm) const {
  const CameraIntrinsics& k = calibration_.depth;
  if (depth_mm.type() != CV_16UC1 || depth_mm.cols != k.width_px || depth_mm.rows != k.height_px) {
    return cv::Mat();
  }
  cv::Mat out(color_.height_px, color_.width_px, CV_16UC1, cv::Scalar(0));
  const int cols = depth_mm.cols;
  const int out_cols = out.cols, out_rows = out.rows;
  uint16_t* const out_data = out.ptr<uint16_t>(0);
  const size_t out_step = out.step1();
  const float tx = static_cast<float>(calibration_.T_color_depth.translation().x());
  const float ty = static_cast<float>(calibration_.T_color_depth.translation().y());
  const float tz = static_cast<float>(calibration_.T_color_depth.translation().z());
  const float fx = static_cast<float>(color_.fx_px), fy = static_cast<float>(color_.fy_px);
  const float cx = static_cast<float>(color_.cx_px), cy = static_cast<float>(color_.cy_px);
  constexpr float kFar = 1e6f;  // far outside the image (and exact as an integer)
  // One row at a time in two passes: the projections of every pixel's footprint, branch-free so
  // that the compiler runs them several pixels per instruction (the depth of an invalid pixel
  // is 0 and its result unused), then the z-buffered splats of the valid pixels.
  std::vector<int> ua(cols), ub(cols), va(cols), vb(cols), value(cols), ok(cols);
  for (int v = 0; v < depth_mm.rows; ++v) {
    const uint16_t* row = depth_mm.ptr<uint16_t>(v);
    const float top_x = row_x_[v], top_y = row_y_[v], top_z = row_z_[v];
    const float bottom_x = row_x_[v + 1], bottom_y = row_y_[v + 1], bottom_z = row_z_[v + 1];
    for (int u = 0; u < cols; ++u) {
      const float z = row[u] * 1e-3f;
      // A point z * ray of the depth camera is z * (column + row) + t in the colour frame. The
      // pixel's footprint: the projections of its top-left and bottom-right corners.
      const float x0 = z * (column_x_[u] + top_x) + tx, y0 = z * (column_y_[u] + top_y) + ty;
      const float z0 = z * (column_z_[u] + top_z) + tz;
      const float x1 = z * (column_x_[u + 1] + bottom_x) + tx;
      const float y1 = z * (column_y_[u + 1] + bottom_y) + ty;
      const float z1 = z * (column_z_[u + 1] + bottom_z) + tz;
      const float inv0 = 1.0f / z0, inv1 = 1.0f / z1;
      const float u0 = fx * x0 * inv0 + cx, v0 = fy * y0 * inv0 + cy;
      const float u1 = fx * x1 * inv1 + cx, v1 = fy * y1 * inv1 + cy;
      // Selects rather than branches (& not &&), so that the loop vectorises.
      const int in_front = (z0 > 1e-6f) & (z1 > 1e-6f) & (row[u] != 0);
      const int near = (std::abs(u0) < kFar) & (std::abs(v0) < kFar) & (std::abs(u1) < kFar) &
                       (std::abs(v1) < kFar);
      ok[u] = in_front & near;
      value[u] = RoundInt(500.0f * (z0 + z1));
      // Colour pixels whose centres lie inside the footprint (else the nearest one).
      const int a = CeilInt(std::min(u0, u1)), b = FloorInt(std::max(u0, u1));
      const int c = CeilInt(std::min(v0, v1)), d = FloorInt(std::max(v0, v1));
      const int uc = RoundInt(0.5f * (u0 + u1)), vc = RoundInt(0.5f * (v0 + v1));
      ua[u] = b < a ? uc : a;
      ub[u] = b < a ? uc : b;
      va[u] = d < c ? vc : c;
      vb[u] = d < c ? vc : d;
    }
    for (int u = 0; u < cols; ++u) {
      if (!ok[u] || value[u] < 1 || value[u] > std::numeric_limits<uint16_t>::max()) continue;
      const uint16_t mm = static_cast<uint16_t>(value[u]);
      const int x_end = std::min(ub[u], out_cols - 1), y_end = std::min(vb[u], out_rows - 1);
      // Nearest surface first (z-buffer; 0 = empty, which wraps to the largest as 0 - 1).
      for (int y = std::max(va[u], 0); y <= y_end; ++y) {
        uint16_t* dst = out_data + y * out_step;
        for (int x = std::max(ua[u], 0); x <= x_end; ++x) {
          if (static_cast<uint16_t>(dst[x] - 1) >= mm) dst[x] = mm;
        }
      }
    }
  }
  return out;
}

}  // namespace icgm
