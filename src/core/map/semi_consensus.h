// Semi-consensus trajectory correction of thesis eq. 6.3/6.4.
//
// Given the chain of the current session L_a, R_(a+1) .. R_b (eq. 6.1: L_k = L_(k-1) (+) R_k),
// where a is the last corrected keyframe and b the current one, and the loop-closure pose L_LC of
// keyframe b (eq. 6.2), the pose difference of eq. 6.3, DeltaPose_Diff = L_LC (-) L_b, is expressed
// in the world frame as D = L_LC * L_b^-1 (so L_LC = D * L_b) with twist xi = GeodesicLog(D).
// The b - a relative poses each receive one equal world-frame increment
//   delta = GeodesicExp(alpha / (b - a) * xi),   R'_k = L_(k-1)^-1 * delta * L_(k-1) * R_k,
// with L_(k-1) the uncorrected pose. Rebuilding with eq. 6.1 gives L'_k = delta^(k-a) * L_k, so
// the correction ramps linearly along the chain and L'_b = GeodesicExp(alpha * xi) * L_b: exactly
// the fraction alpha of the difference (alpha = 1 reaches full consensus L'_b = L_LC). The thesis
// writes [R_a .. R_b] but divides by b - a; R_a links a to a-1 and is left untouched here so the
// already corrected part of the map does not move. 0 < alpha < 1 while mapping, 1 while localizing.
#pragma once

#include <vector>

#include "core/common/pose.h"

namespace icgm {

// Returns R'_(a+1) .. R'_b. `relative_poses` must be non-empty; alpha in [0, 1].
std::vector<Pose3> SemiConsensusCorrection(const Pose3& pose_a,
                                           const std::vector<Pose3>& relative_poses,
                                           const Pose3& loop_closure_pose, double alpha);

}  // namespace icgm
