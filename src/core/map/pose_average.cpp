#include "core/map/pose_average.h"

#include <string>

#include "core/map/se3_geodesic.h"

namespace icgm {

Status AveragePoses(const std::vector<WeightedPose>& hypotheses, Pose3* mean, int max_iterations) {
  if (hypotheses.empty()) return Status::Error("pose average: no hypotheses");
  Mat6 total = Mat6::Zero();
  size_t best = 0;
  for (size_t i = 0; i < hypotheses.size(); ++i) {
    total += hypotheses[i].information;
    if (hypotheses[i].information.trace() > hypotheses[best].information.trace()) best = i;
  }
  const Eigen::LDLT<Mat6> solver(total);
  if (solver.info() != Eigen::Success || !solver.isPositive() ||
      solver.vectorD().minCoeff() <= 1e-12) {
    return Status::Error("pose average: total information is singular");
  }
  // Start from the most certain hypothesis: it is inside the cluster of consistent poses.
  Pose3 current = hypotheses[best].pose;
  for (int it = 0; it < max_iterations; ++it) {
    Vec6 gradient = Vec6::Zero();
    for (const auto& h : hypotheses) {
      gradient += h.information * GeodesicLog(current.inverse() * h.pose);
    }
    const Vec6 delta = solver.solve(gradient);
    current = Orthonormalized(current * GeodesicExp(delta));
    if (delta.norm() < 1e-12) break;
  }
  *mean = current;
  return Status::Ok();
}

}  // namespace icgm
