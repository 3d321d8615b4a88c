#include "core/common/planar_scan.h"

namespace icgm {

std::vector<Eigen::Vector3d> ScanPointsInBase(const PlanarScan& scan, const Pose3& T_base_scanner) {
  std::vector<Eigen::Vector3d> points;
  points.reserve(scan.ranges_m.size());
  for (size_t i = 0; i < scan.ranges_m.size(); ++i) {
    const float r = scan.ranges_m[i];
    if (!scan.IsReturn(r)) continue;
    const double a = scan.BeamAngle(i);
    points.push_back(T_base_scanner * Eigen::Vector3d(r * std::cos(a), r * std::sin(a), 0.0));
  }
  return points;
}

}  // namespace icgm
