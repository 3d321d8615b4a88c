// Closed-form absolute orientation (Horn, "Closed-form solution of absolute orientation using
// unit quaternions", JOSA A 4(4), 1987): the similarity (s, R, t) that best maps a set of
// source points onto corresponding destination points.
#pragma once

#include <vector>

#include <Eigen/Core>

#include "core/common/pose.h"
#include "core/common/status.h"

namespace icgm {

// dst = scale * rotation * src + translation.
struct SimilarityTransform {
  Eigen::Matrix3d rotation = Eigen::Matrix3d::Identity();
  Eigen::Vector3d translation = Eigen::Vector3d::Zero();
  double scale = 1.0;

  // The rigid part (rotation, translation); the scale is ignored.
  Pose3 AsPose() const;
  // scale * rotation * p + translation.
  Eigen::Vector3d Apply(const Eigen::Vector3d& p) const;
};

// Horn (1987) closed-form absolute orientation with unit quaternions. Minimizes
//   sum_i w_i |dst_i - (s R src_i + t)|^2
// over R (and t); the rotation is the eigenvector of the largest eigenvalue of Horn's 4x4
// symmetric matrix N built from the weighted cross-covariance of the centred points (Horn
// sec. 4), the translation maps the weighted centroids onto each other (sec. 2.C).
// With estimate_scale the scale is Horn's symmetric estimate (sec. 2.E),
//   s = sqrt(sum w_i |dst_i - dst_c|^2 / sum w_i |src_i - src_c|^2),
// which is exact for noise-free data and does not depend on R; estimate_scale=false gives an
// SE(3) result with scale 1. `weights` (optional) must be finite, non-negative, one per point,
// with a positive sum. Fails (Status with reason, *out untouched) for < 3 points, size
// mismatch, non-finite input, bad weights or degenerate configurations (all points coincident
// or collinear, where the rotation about the line is undetermined).
Status HornAlign(const std::vector<Eigen::Vector3d>& src, const std::vector<Eigen::Vector3d>& dst,
                 bool estimate_scale, SimilarityTransform* out,
                 const std::vector<double>* weights = nullptr);

}  // namespace icgm
