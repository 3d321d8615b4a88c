// ATE with the estimate aligned by its first pose instead of a least-squares fit: the fallback
// for trajectories whose positions are (nearly) collinear, e.g. a straight drive, where Horn's
// alignment is undetermined about the line (core/eval refuses them). Anchoring at the first
// pose charges every later error to the estimate, so it is an upper bound of the fitted ATE.
#pragma once

#include <cstddef>

#include "core/common/status.h"
#include "core/dataset/trajectory.h"

namespace icgm::tools {

struct FirstPoseAte {
  double rmse_m = 0.0;
  double max_m = 0.0;
  size_t count = 0;
};

// `groundtruth` sorted by stamp; estimate poses are compared with the ground truth at their
// stamps (PoseAt, interpolated over gaps up to max_gap_s). Fails when the first estimate pose
// or fewer than 3 poses have ground truth.
Status EvaluateFirstPoseAte(const Trajectory& groundtruth, const Trajectory& estimate,
                            double max_gap_s, FirstPoseAte* out);

}  // namespace icgm::tools
