#include "core/registration/pose_refinement.h"

#include <cmath>

#include <Eigen/Dense>

namespace icgm {

Eigen::Matrix3d Skew(const Eigen::Vector3d& v) {
  Eigen::Matrix3d s;
  s << 0, -v.z(), v.y(), v.z(), 0, -v.x(), -v.y(), v.x(), 0;
  return s;
}

Eigen::Matrix<double, 2, 3> ProjectionJacobian(const Eigen::Vector3d& x,
                                               const CameraIntrinsics& k) {
  const double iz = 1.0 / x.z();
  Eigen::Matrix<double, 2, 3> j;
  j << k.fx_px * iz, 0, -k.fx_px * x.x() * iz * iz, 0, k.fy_px * iz, -k.fy_px * x.y() * iz * iz;
  return j;
}

namespace {

using Mat26 = Eigen::Matrix<double, 2, 6>;

double HuberWeight(double r, double delta) { return r <= delta ? 1.0 : delta / r; }

struct Accumulated {
  Mat6 h = Mat6::Zero();
  Vec6 b = Vec6::Zero();
  double cost = 0.0;     // weighted squared residuals
  size_t residuals = 0;  // 2-D residual count
};

// Builds the normal equations of the symmetric transfer error at `pose`.
bool Accumulate(const std::vector<Eigen::Vector3d>& pr, const std::vector<cv::Point2f>& ur,
                const std::vector<Eigen::Vector3d>& pc, const std::vector<cv::Point2f>& uc,
                const std::vector<int>& indices, const CameraIntrinsics& k, double huber,
                const std::vector<double>* sigma_px, const Pose3& pose, Accumulated* acc) {
  const Eigen::Matrix3d r = pose.linear();
  const Pose3 inv = pose.inverse();
  for (int i : indices) {
    const double inv_sigma = sigma_px ? 1.0 / (*sigma_px)[i] : 1.0;
    // Current point into the reference image: X = T P_cur; dX/d(eps_t) = R, dX/d(eps_w) = -R[P]x.
    const Eigen::Vector3d x = pose * pc[i];
    if (x.z() > 1e-6) {
      const Eigen::Vector2d e = inv_sigma * (k.Project(x) - Eigen::Vector2d(ur[i].x, ur[i].y));
      Eigen::Matrix<double, 3, 6> dx;
      dx << r, -r * Skew(pc[i]);
      const Mat26 j = inv_sigma * ProjectionJacobian(x, k) * dx;
      const double w = HuberWeight(e.norm(), huber);
      acc->h += w * j.transpose() * j;
      acc->b += w * j.transpose() * e;
      acc->cost += w * e.squaredNorm();
      ++acc->residuals;
    }
    // Reference point into the current image: Y = Exp(-eps) T^-1 P_ref; dY = -eps_t - eps_w x Y.
    const Eigen::Vector3d y = inv * pr[i];
    if (y.z() > 1e-6) {
      const Eigen::Vector2d e = inv_sigma * (k.Project(y) - Eigen::Vector2d(uc[i].x, uc[i].y));
      Eigen::Matrix<double, 3, 6> dy;
      dy << -Eigen::Matrix3d::Identity(), Skew(y);
      const Mat26 j = inv_sigma * ProjectionJacobian(y, k) * dy;
      const double w = HuberWeight(e.norm(), huber);
      acc->h += w * j.transpose() * j;
      acc->b += w * j.transpose() * e;
      acc->cost += w * e.squaredNorm();
      ++acc->residuals;
    }
  }
  return acc->residuals * 2 > 6;
}

// sigma^2 H^-1 with sigma^2 estimated from the residuals; identity when H is singular.
Mat6 CovarianceFrom(const Mat6& h, double cost, size_t scalar_residuals) {
  Eigen::FullPivLU<Mat6> lu(h);
  if (!lu.isInvertible() || scalar_residuals <= 6) return Mat6::Identity();
  const double sigma_sq = cost / static_cast<double>(scalar_residuals - 6);
  Mat6 c = sigma_sq * lu.inverse();
  return 0.5 * (c + c.transpose());
}

}  // namespace

Status RefinePoseByReprojection(const std::vector<Eigen::Vector3d>& points_ref,
                                const std::vector<cv::Point2f>& pixels_ref,
                                const std::vector<Eigen::Vector3d>& points_cur,
                                const std::vector<cv::Point2f>& pixels_cur,
                                const std::vector<int>& indices, const CameraIntrinsics& intrinsics,
                                const ReprojectionRefineOptions& options, Pose3* pose,
                                Mat6* covariance, double* rms_px,
                                const std::vector<double>* pixel_sigma_px) {
  if (indices.size() < 3) return Status::Error("reprojection refinement needs >= 3 points");
  if (pixel_sigma_px) {
    if (pixel_sigma_px->size() != points_ref.size()) {
      return Status::Error("reprojection refinement: one pixel sigma per point needed");
    }
    for (int i : indices) {
      if (!((*pixel_sigma_px)[i] > 0.0)) return Status::Error("pixel sigma must be > 0");
    }
  }
  Pose3 current = *pose;
  Accumulated acc;
  if (!Accumulate(points_ref, pixels_ref, points_cur, pixels_cur, indices, intrinsics,
                  options.huber_px, pixel_sigma_px, current, &acc)) {
    return Status::Error("reprojection refinement: points behind the camera");
  }
  for (int it = 0; it < options.max_iterations; ++it) {
    Eigen::LDLT<Mat6> ldlt(acc.h);
    if (ldlt.info() != Eigen::Success) return Status::Error("reprojection refinement: singular");
    const Vec6 step = ldlt.solve(-acc.b);
    if (!step.allFinite()) return Status::Error("reprojection refinement: singular");
    const Pose3 candidate = Orthonormalized(current * ExpSE3(step));
    Accumulated next;
    if (!Accumulate(points_ref, pixels_ref, points_cur, pixels_cur, indices, intrinsics,
                    options.huber_px, pixel_sigma_px, candidate, &next) ||
        !(next.cost <= acc.cost)) {
      break;  // Gauss-Newton overshoot near the minimum: keep the last accepted pose.
    }
    current = candidate;
    acc = next;
    if (step.norm() < options.min_step) break;
  }
  *pose = current;
  const size_t scalar = 2 * acc.residuals;
  if (covariance) *covariance = CovarianceFrom(acc.h, acc.cost, scalar);
  if (rms_px) *rms_px = std::sqrt(acc.cost / std::max<size_t>(1, acc.residuals));
  return Status::Ok();
}

Mat6 PointToPointCovariance(const std::vector<Eigen::Vector3d>& points_ref,
                            const std::vector<Eigen::Vector3d>& points_cur,
                            const std::vector<int>& indices, const Pose3& pose) {
  // r = T P_cur - P_ref; dr/d(eps_t) = R, dr/d(eps_w) = -R [P_cur]x.
  const Eigen::Matrix3d r = pose.linear();
  Mat6 h = Mat6::Zero();
  double cost = 0.0;
  for (int i : indices) {
    Eigen::Matrix<double, 3, 6> j;
    j << r, -r * Skew(points_cur[i]);
    h += j.transpose() * j;
    cost += (pose * points_cur[i] - points_ref[i]).squaredNorm();
  }
  return CovarianceFrom(h, cost, 3 * indices.size());
}

}  // namespace icgm
