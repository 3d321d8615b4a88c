// RgbdObservationError without depth (depth 0, depth sigma 0: the third residual is zero) as
// ceres::AutoDiffCostFunction<RgbdObservationError, 3, 3, 4, 3> evaluates it, bit for bit: the
// same dual-number operations in the same order (ceres::Jet, Eigen's quaternion rotation and
// cross product), but each intermediate carries only the derivative entries that can be
// nonzero (x - t two, a quaternion coefficient one, ...) where the automatic version works on
// all ten everywhere. The bundle adjustment without depth uses it. Include only where Ceres is
// available (ICGM_HAVE_CERES).
#pragma once

#include <ceres/ceres.h>

#include "core/optimization/ceres_costs.h"

namespace icgm {

class PixelObservationCost : public ceres::SizedCostFunction<3, 3, 4, 3> {
 public:
  PixelObservationCost(const CameraIntrinsics& k, const Eigen::Vector2d& pixel, double sigma_px)
      : functor_(k, pixel, sigma_px, 0.0, 0.0) {}

  bool Evaluate(double const* const* parameters, double* residuals,
                double** jacobians) const override;

 private:
  RgbdObservationError functor_;
};

}  // namespace icgm
