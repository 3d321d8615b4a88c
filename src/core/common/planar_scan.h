// A planar range scan: a 2-D laser scanner (or a ring of range sensors) as sensor_msgs/LaserScan
// carries it. Beam i points at angle_min_rad + i * angle_increment_rad in the scanner's frame
// (x forward, y left, angles counter-clockwise about z); ranges in metres. A range that is not
// finite or lies outside [range_min_m, range_max_m] is no return: nothing within range.
#pragma once

#include <cmath>
#include <vector>

#include <Eigen/Core>

#include "core/common/pose.h"
#include "core/common/time.h"

namespace icgm {

struct PlanarScan {
  Time stamp;
  double angle_min_rad = 0.0;
  double angle_increment_rad = 0.0;
  double range_min_m = 0.0;
  double range_max_m = 0.0;
  std::vector<float> ranges_m;

  double BeamAngle(size_t i) const { return angle_min_rad + static_cast<double>(i) * angle_increment_rad; }
  bool IsReturn(float range_m) const {
    return std::isfinite(range_m) && range_m >= range_min_m && range_m <= range_max_m;
  }
};

// The scan's returns as points in base_link: each range along its beam in the scanner's plane,
// moved by T_base_scanner (the scanner's mounting on the base). No returns are skipped.
std::vector<Eigen::Vector3d> ScanPointsInBase(const PlanarScan& scan, const Pose3& T_base_scanner);

}  // namespace icgm
