// Test helper: exact depth images of a flat floor with upright boxes, seen by a pinhole camera
// on base_link (the simulator's conventions: base_link x forward, z up; optical frame x right,
// y down, z forward).
#pragma once

#include <cmath>
#include <limits>
#include <vector>

#include <opencv2/core.hpp>

#include "core/common/camera.h"
#include "core/common/planar_scan.h"
#include "core/common/pose.h"

namespace icgm::test {

struct Box {  // axis-aligned in the map frame, standing on the floor
  double min_x, max_x, min_y, max_y, height;
};

inline CameraIntrinsics SmallCamera() {
  CameraIntrinsics k;
  k.fx_px = k.fy_px = 131.25;
  k.cx_px = 79.5;
  k.cy_px = 59.5;
  k.width_px = 160;
  k.height_px = 120;
  return k;
}

// Camera 1 m above the floor at the base's origin, looking forward, pitched down.
inline Pose3 MountPose(double pitch_down_deg = 15.0) {
  Eigen::Matrix3d r0;
  r0.col(0) = Vec3(0, -1, 0);
  r0.col(1) = Vec3(0, 0, -1);
  r0.col(2) = Vec3(1, 0, 0);
  Pose3 p = Pose3::Identity();
  p.linear() = Eigen::AngleAxisd(pitch_down_deg * M_PI / 180.0, Vec3::UnitY()) * r0;
  p.translation() = Vec3(0, 0, 1.0);
  return p;
}

// Ray casting against the floor (z = 0) and the boxes' sides and tops; NaN beyond max_range_m.
inline cv::Mat RenderDepth(const CameraIntrinsics& k, const Pose3& T_map_camera,
                           const std::vector<Box>& boxes, double max_range_m = 6.0) {
  cv::Mat depth(k.height_px, k.width_px, CV_32F);
  const Vec3 o = T_map_camera.translation();
  for (int v = 0; v < k.height_px; ++v) {
    for (int u = 0; u < k.width_px; ++u) {
      const Vec3 ray_cam((u - k.cx_px) / k.fx_px, (v - k.cy_px) / k.fy_px, 1.0);
      const Vec3 d = T_map_camera.linear() * ray_cam;  // depth = parameter along this ray
      double best = std::numeric_limits<double>::infinity();
      if (d.z() < 0) best = -o.z() / d.z();
      for (const Box& b : boxes) {
        // Slab intersection with the box [min, max] x [min, max] x [0, height].
        double t0 = 0.0, t1 = std::numeric_limits<double>::infinity();
        const double lo[3] = {b.min_x, b.min_y, 0.0}, hi[3] = {b.max_x, b.max_y, b.height};
        bool hit = true;
        for (int a = 0; a < 3 && hit; ++a) {
          if (std::abs(d[a]) < 1e-12) {
            hit = o[a] >= lo[a] && o[a] <= hi[a];
            continue;
          }
          double ta = (lo[a] - o[a]) / d[a], tb = (hi[a] - o[a]) / d[a];
          if (ta > tb) std::swap(ta, tb);
          t0 = std::max(t0, ta);
          t1 = std::min(t1, tb);
          hit = t0 <= t1;
        }
        if (hit && t0 > 0) best = std::min(best, t0);
      }
      depth.at<float>(v, u) =
          best <= max_range_m ? static_cast<float>(best) : std::numeric_limits<float>::quiet_NaN();
    }
  }
  return depth;
}

// A planar scan from a scanner on the robot's base origin at height_m (robot at `base`, map
// frame; the beams in base_link, counter-clockwise from forward): 2-D slab intersection with the
// boxes reaching the plane; +infinity where a beam returns nothing within range_max_m.
inline PlanarScan RenderBoxScan(Time stamp, double base_x_m, double base_y_m, double base_yaw_rad,
                                const std::vector<Box>& boxes, int beams = 360,
                                double height_m = 1.0, double range_max_m = 6.0) {
  PlanarScan scan;
  scan.stamp = stamp;
  scan.angle_min_rad = 0.0;
  scan.angle_increment_rad = 2.0 * M_PI / beams;
  scan.range_min_m = 0.1;
  scan.range_max_m = range_max_m;
  scan.ranges_m.assign(static_cast<size_t>(beams), std::numeric_limits<float>::infinity());
  for (int i = 0; i < beams; ++i) {
    const double a = base_yaw_rad + i * scan.angle_increment_rad;
    const double o[2] = {base_x_m, base_y_m}, d[2] = {std::cos(a), std::sin(a)};
    double best = range_max_m;
    for (const Box& b : boxes) {
      if (b.height < height_m) continue;
      const double lo[2] = {b.min_x, b.min_y}, hi[2] = {b.max_x, b.max_y};
      double t0 = 0.0, t1 = std::numeric_limits<double>::infinity();
      for (int k = 0; k < 2; ++k) {
        if (std::abs(d[k]) < 1e-12) {
          if (o[k] < lo[k] || o[k] > hi[k]) t0 = t1 + 1.0;
          continue;
        }
        const double ta = (lo[k] - o[k]) / d[k], tb = (hi[k] - o[k]) / d[k];
        t0 = std::max(t0, std::min(ta, tb));
        t1 = std::min(t1, std::max(ta, tb));
      }
      if (t0 <= t1 && t0 > 0.0) best = std::min(best, t0);
    }
    if (best < range_max_m) scan.ranges_m[static_cast<size_t>(i)] = static_cast<float>(best);
  }
  return scan;
}

}  // namespace icgm::test
