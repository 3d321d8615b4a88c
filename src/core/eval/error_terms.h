// Which systematic terms explain an aligned trajectory's error (a diagnostic beside the ATE).
// Per axis k of the first ground-truth camera frame (x right, y down, z along the optical axis)
// the aligned estimate's position error is fitted by least squares as
//   e_k(t) = lead_s_k * v_k(t) + scale_error_k * d_k(t) + c_k
// with v the ground-truth velocity and d the ground-truth displacement from the first pose,
// both in that frame.
//  - lead_s_k > 0: the estimate is ahead of the ground truth along axis k by that much time
//    (a capture instant later than the stamp, rolling shutter, or a clock offset); < 0 behind.
//  - scale_error_k: motion along axis k is estimated (1 + scale_error_k) times the true one
//    (wrong focal length or depth scale).
// The residual after the fit is what neither term explains (noise, non-linear effects).
#pragma once

#include "core/common/status.h"
#include "core/dataset/trajectory.h"
#include "core/eval/trajectory_evaluation.h"

namespace icgm {

struct ErrorTerms {
  Vec3 lead_s = Vec3::Zero();
  Vec3 scale_error = Vec3::Zero();
  Vec3 offset_m = Vec3::Zero();
  double ate_rmse_m = 0.0;          // of the poses used
  double rmse_after_lead_m = 0.0;   // residual with the lead term (and offset) only
  double rmse_after_scale_m = 0.0;  // with the scale term (and offset) only
  double rmse_after_both_m = 0.0;
  size_t poses = 0;                 // associated poses with a ground-truth velocity
};

// `evaluation` from EvaluateTrajectory on `groundtruth`. The velocity at each pose is the
// central difference of the ground truth over +-velocity_half_window_s. Fails with fewer than
// 10 usable poses or a motion that leaves an axis unobservable.
Status FitErrorTerms(const Trajectory& groundtruth, const TrajectoryEvaluation& evaluation,
                     ErrorTerms* out, double velocity_half_window_s = 0.02);

}  // namespace icgm
