// Figures of a monocular trajectory against ground truth: the Sim(3)-aligned ATE (the scale of
// a monocular map is arbitrary; trajectory_evaluation.h with estimate_scale) and that error in
// per cent of the distance travelled, the figure of thesis Table 6.5.
#pragma once

#include "core/common/status.h"
#include "core/dataset/trajectory.h"
#include "core/eval/trajectory_evaluation.h"

namespace icgm {

struct MonoEvaluation {
  TrajectoryEvaluation evaluation;  // Sim(3) alignment
  double distance_m = 0.0;          // ground-truth path length over the associated poses
  double error_percent = 0.0;       // 100 * ATE RMSE / distance_m
  double scale = 1.0;               // Sim(3) scale, metres per map unit
};

// Length of the polyline through the positions, in order.
double PathLengthM(const std::vector<Pose3>& poses);

// Sim(3) ATE of `estimate` against `groundtruth` (association within max_dt_s); fails like
// EvaluateTrajectory, or when the associated ground truth does not move.
Status EvaluateMonoTrajectory(const Trajectory& groundtruth, const Trajectory& estimate,
                              double max_dt_s, MonoEvaluation* out);

}  // namespace icgm
