#include "core/geometry/absolute_orientation.h"

#include <cmath>
#include <string>

#include <Eigen/Eigenvalues>
#include <Eigen/Geometry>

namespace icgm {

namespace {

// A point set whose weighted scatter has a second-largest eigenvalue below this fraction of
// the largest is treated as collinear (rotation about the line is then undetermined).
constexpr double kCollinearRatio = 1e-12;

// Returns true when the weighted, centred points span at least a plane.
bool SpansPlane(const Eigen::Matrix3d& scatter) {
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> es(scatter, Eigen::EigenvaluesOnly);
  const Eigen::Vector3d ev = es.eigenvalues();  // ascending
  return ev(2) > 0.0 && ev(1) > kCollinearRatio * ev(2);
}

}  // namespace

Pose3 SimilarityTransform::AsPose() const {
  Pose3 p = Pose3::Identity();
  p.linear() = rotation;
  p.translation() = translation;
  return p;
}

Eigen::Vector3d SimilarityTransform::Apply(const Eigen::Vector3d& p) const {
  return scale * (rotation * p) + translation;
}

Status HornAlign(const std::vector<Eigen::Vector3d>& src, const std::vector<Eigen::Vector3d>& dst,
                 bool estimate_scale, SimilarityTransform* out,
                 const std::vector<double>* weights) {
  const size_t n = src.size();
  if (n != dst.size()) {
    return Status::Error("horn: size mismatch, " + std::to_string(n) + " source vs " +
                         std::to_string(dst.size()) + " destination points");
  }
  if (n < 3) return Status::Error("horn: need at least 3 points, got " + std::to_string(n));
  if (weights != nullptr && weights->size() != n) {
    return Status::Error("horn: " + std::to_string(weights->size()) + " weights for " +
                         std::to_string(n) + " points");
  }
  double w_sum = 0.0;
  Eigen::Vector3d src_c = Eigen::Vector3d::Zero();
  Eigen::Vector3d dst_c = Eigen::Vector3d::Zero();
  for (size_t i = 0; i < n; ++i) {
    const double w = weights ? (*weights)[i] : 1.0;
    if (!std::isfinite(w) || w < 0.0) {
      return Status::Error("horn: weight " + std::to_string(i) + " is negative or not finite");
    }
    if (!src[i].allFinite() || !dst[i].allFinite()) {
      return Status::Error("horn: point " + std::to_string(i) + " is not finite");
    }
    w_sum += w;
    src_c += w * src[i];
    dst_c += w * dst[i];
  }
  if (!(w_sum > 0.0)) return Status::Error("horn: weights sum to zero");
  src_c /= w_sum;
  dst_c /= w_sum;

  // Weighted cross-covariance M = sum w (src - src_c)(dst - dst_c)^T (Horn's S_xy = M(x, y)),
  // plus the scatter of each set for the degeneracy test and the symmetric scale.
  Eigen::Matrix3d m = Eigen::Matrix3d::Zero();
  Eigen::Matrix3d src_scatter = Eigen::Matrix3d::Zero();
  Eigen::Matrix3d dst_scatter = Eigen::Matrix3d::Zero();
  for (size_t i = 0; i < n; ++i) {
    const double w = weights ? (*weights)[i] : 1.0;
    const Eigen::Vector3d a = src[i] - src_c;
    const Eigen::Vector3d b = dst[i] - dst_c;
    m += w * a * b.transpose();
    src_scatter += w * a * a.transpose();
    dst_scatter += w * b * b.transpose();
  }
  if (!SpansPlane(src_scatter)) {
    return Status::Error("horn: degenerate source points (coincident or collinear)");
  }
  if (!SpansPlane(dst_scatter)) {
    return Status::Error("horn: degenerate destination points (coincident or collinear)");
  }

  // Horn eq. (Sec. 4.A): N is symmetric and traceless; its top eigenvector is the unit
  // quaternion (q0, qx, qy, qz) of the rotation taking src onto dst.
  const double sxx = m(0, 0), sxy = m(0, 1), sxz = m(0, 2);
  const double syx = m(1, 0), syy = m(1, 1), syz = m(1, 2);
  const double szx = m(2, 0), szy = m(2, 1), szz = m(2, 2);
  Eigen::Matrix4d nmat;
  nmat << sxx + syy + szz, syz - szy, szx - sxz, sxy - syx,  //
      syz - szy, sxx - syy - szz, sxy + syx, szx + sxz,      //
      szx - sxz, sxy + syx, -sxx + syy - szz, syz + szy,     //
      sxy - syx, szx + sxz, syz + szy, -sxx - syy + szz;
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix4d> es(nmat);
  if (es.info() != Eigen::Success) return Status::Error("horn: eigen decomposition failed");
  const Eigen::Vector4d q = es.eigenvectors().col(3);  // eigenvalues ascending
  const Eigen::Quaterniond quat(q(0), q(1), q(2), q(3));

  SimilarityTransform result;
  result.rotation = quat.normalized().toRotationMatrix();
  if (estimate_scale) {
    result.scale = std::sqrt(dst_scatter.trace() / src_scatter.trace());
  }
  result.translation = dst_c - result.scale * (result.rotation * src_c);
  *out = result;
  return Status::Ok();
}

}  // namespace icgm
