// Trajectory accuracy against ground truth, following the TUM RGB-D benchmark (Sturm et al.,
// "A Benchmark for the Evaluation of RGB-D SLAM Systems", IROS 2012, sec. V):
//  - association: estimate and ground-truth stamps paired one-to-one within max_dt_s
//    (AssociateStamps, as associate.py);
//  - ATE: the estimate's positions are aligned to the ground truth's with Horn's method
//    (SE(3), or Sim(3) for monocular estimates with an unknown scale), then
//    e_i = |p_gt_i - (s R p_est_i + t)| (translational part of the paper's F_i = Q_i^-1 S P_i);
//  - RPE: for each associated pose i, j is the first associated pose at least rpe_delta_s
//    later; E_ij = (Q_i^-1 Q_j)^-1 (P_i^-1 P_j) on the aligned estimate. Its
//    translation norm and rotation angle are divided by t_j - t_i, giving m/s and deg/s
//    (the benchmark's "per second" figures with rpe_delta_s = 1).
#pragma once

#include <vector>

#include "core/common/pose.h"
#include "core/common/status.h"
#include "core/dataset/trajectory.h"
#include "core/eval/error_stats.h"
#include "core/geometry/absolute_orientation.h"

namespace icgm {

struct TrajectoryEvalOptions {
  double max_dt_s = 0.02;       // association window
  bool estimate_scale = false;  // Sim(3) alignment (monocular), else SE(3)
  double rpe_delta_s = 1.0;     // RPE time step
};

struct TrajectoryEvaluation {
  size_t num_groundtruth = 0;
  size_t num_estimate = 0;
  // Maps estimate coordinates onto ground-truth coordinates: p_gt ~ alignment.Apply(p_est).
  SimilarityTransform alignment;

  // Per associated pose, in stamp order (estimate stamps).
  std::vector<Time> stamps;
  std::vector<Pose3> groundtruth;
  std::vector<Pose3> aligned_estimate;  // rotation R*R_est, translation s*R*t_est + t
  std::vector<double> ate_m;

  ErrorStats ate;                      // metres
  ErrorStats rpe_translation_m_per_s;  // empty (count 0) if shorter than rpe_delta_s
  ErrorStats rpe_rotation_deg_per_s;

  size_t num_associated() const { return stamps.size(); }
};

// Applies a similarity to a pose: rotation R * R_p, translation s * R * t_p + t.
Pose3 ApplySimilarity(const SimilarityTransform& s, const Pose3& pose);

// Evaluates `estimate` against `groundtruth` (either may be unsorted; both are sorted by stamp
// internally). Fails with a reason for invalid options, fewer than 3 associated poses, or
// estimate positions that cannot be aligned (coincident or collinear).
Status EvaluateTrajectory(const Trajectory& groundtruth, const Trajectory& estimate,
                          const TrajectoryEvalOptions& options, TrajectoryEvaluation* out);

}  // namespace icgm
