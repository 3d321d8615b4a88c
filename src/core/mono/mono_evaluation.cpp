#include "core/mono/mono_evaluation.h"

namespace icgm {

double PathLengthM(const std::vector<Pose3>& poses) {
  double length = 0.0;
  for (size_t i = 1; i < poses.size(); ++i) {
    length += (poses[i].translation() - poses[i - 1].translation()).norm();
  }
  return length;
}

Status EvaluateMonoTrajectory(const Trajectory& groundtruth, const Trajectory& estimate,
                              double max_dt_s, MonoEvaluation* out) {
  TrajectoryEvalOptions options;
  options.max_dt_s = max_dt_s;
  options.estimate_scale = true;
  const Status s = EvaluateTrajectory(groundtruth, estimate, options, &out->evaluation);
  if (!s.ok()) return s;
  out->distance_m = PathLengthM(out->evaluation.groundtruth);
  if (!(out->distance_m > 1e-9)) return Status::Error("the ground truth does not move");
  out->error_percent = 100.0 * out->evaluation.ate.rmse / out->distance_m;
  out->scale = out->evaluation.alignment.scale;
  return Status::Ok();
}

}  // namespace icgm
