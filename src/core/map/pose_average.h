// Pose-set optimization of thesis eq. 6.2: the loop-closure pose of the current model is
//   L_LoopClosure = argmin_L  sum_i || (L_li (+) beta_i) (-) L ||^2_{Omega_i}
// i.e. a weighted (Mahalanobis) mean on SE(3). Each hypothesis P_i = L_li (+) beta_i comes with
// an information matrix Omega_i in its own tangent space (twist layout of se3_geodesic.h).
// Solved by Gauss-Newton on the manifold: r_i = GeodesicLog(L^-1 P_i),
// delta = (sum Omega_i)^-1 sum Omega_i r_i, L <- L * GeodesicExp(delta), until |delta| is tiny.
// For hypotheses that are symmetric around a pose T (T*Exp(e), T*Exp(-e)) the result is exactly T.
#pragma once

#include <vector>

#include "core/common/pose.h"
#include "core/common/status.h"

namespace icgm {

struct WeightedPose {
  Pose3 pose = Pose3::Identity();
  Mat6 information = Mat6::Identity();
};

// Fails (with a reason) on an empty set or a singular total information.
Status AveragePoses(const std::vector<WeightedPose>& hypotheses, Pose3* mean,
                    int max_iterations = 30);

}  // namespace icgm
