#include "tools/first_pose_ate.h"

#include <algorithm>
#include <cmath>
#include <optional>

namespace icgm::tools {

Status EvaluateFirstPoseAte(const Trajectory& groundtruth, const Trajectory& estimate,
                            double max_gap_s, FirstPoseAte* out) {
  *out = FirstPoseAte();
  if (estimate.empty()) return Status::Error("empty estimate");
  const std::optional<Pose3> gt0 = PoseAt(groundtruth, estimate.front().stamp, max_gap_s);
  if (!gt0) return Status::Error("no ground truth at the first estimate pose");
  // Maps estimate coordinates onto ground-truth coordinates.
  const Pose3 align = *gt0 * estimate.front().pose.inverse();
  double sum_sq = 0.0;
  for (const StampedPose& e : estimate) {
    const std::optional<Pose3> gt = PoseAt(groundtruth, e.stamp, max_gap_s);
    if (!gt) continue;
    const double d = ((align * e.pose).translation() - gt->translation()).norm();
    sum_sq += d * d;
    out->max_m = std::max(out->max_m, d);
    ++out->count;
  }
  if (out->count < 3) return Status::Error("fewer than 3 poses with ground truth");
  out->rmse_m = std::sqrt(sum_sq / out->count);
  return Status::Ok();
}

}  // namespace icgm::tools
