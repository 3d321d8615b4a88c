#include "core/eval/error_terms.h"

#include <cmath>
#include <optional>
#include <vector>

#include <Eigen/Dense>

namespace icgm {

namespace {

// Per-axis least squares of e on the columns of X; returns the coefficients and adds the
// squared residuals to *sum_sq.
Eigen::VectorXd FitAxis(const Eigen::MatrixXd& X, const Eigen::VectorXd& e, double* sum_sq) {
  const Eigen::VectorXd b = X.colPivHouseholderQr().solve(e);
  *sum_sq += (e - X * b).squaredNorm();
  return b;
}

}  // namespace

Status FitErrorTerms(const Trajectory& groundtruth, const TrajectoryEvaluation& ev,
                     ErrorTerms* out, double velocity_half_window_s) {
  *out = ErrorTerms();
  if (!(velocity_half_window_s > 0.0)) return Status::Error("velocity window must be > 0");
  if (ev.groundtruth.empty()) return Status::Error("no associated poses");
  const Pose3& first = ev.groundtruth.front();
  const Eigen::Matrix3d to_first = first.rotation().transpose();
  const int64_t half_ns = static_cast<int64_t>(std::llround(velocity_half_window_s * 1e9));
  std::vector<Vec3> err, vel, disp;
  for (size_t i = 0; i < ev.num_associated(); ++i) {
    const int64_t t = ev.stamps[i].nanoseconds();
    const std::optional<Pose3> a =
        PoseAt(groundtruth, Time::FromNanoseconds(t - half_ns), 2 * velocity_half_window_s);
    const std::optional<Pose3> b =
        PoseAt(groundtruth, Time::FromNanoseconds(t + half_ns), 2 * velocity_half_window_s);
    if (!a || !b) continue;
    vel.push_back(to_first * (b->translation() - a->translation()) /
                  (2.0 * velocity_half_window_s));
    err.push_back(to_first *
                  (ev.aligned_estimate[i].translation() - ev.groundtruth[i].translation()));
    disp.push_back(to_first * (ev.groundtruth[i].translation() - first.translation()));
  }
  const Eigen::Index n = static_cast<Eigen::Index>(err.size());
  if (n < 10) return Status::Error("fewer than 10 poses with a ground-truth velocity");
  double sum_lead = 0.0, sum_scale = 0.0, sum_both = 0.0, sum_ate = 0.0;
  for (int k = 0; k < 3; ++k) {
    Eigen::VectorXd e(n);
    Eigen::MatrixXd both(n, 3);
    for (Eigen::Index i = 0; i < n; ++i) {
      e(i) = err[i](k);
      both.row(i) << vel[i](k), disp[i](k), 1.0;
      sum_ate += e(i) * e(i);
    }
    for (int c = 0; c < 2; ++c) {
      if (both.col(c).norm() < 1e-9) {
        return Status::Error(std::string("no motion along camera axis ") + "xyz"[k]);
      }
    }
    Eigen::MatrixXd lead_only(n, 2), scale_only(n, 2);
    lead_only << both.col(0), both.col(2);
    scale_only << both.col(1), both.col(2);
    FitAxis(lead_only, e, &sum_lead);
    FitAxis(scale_only, e, &sum_scale);
    const Eigen::VectorXd b = FitAxis(both, e, &sum_both);
    out->lead_s(k) = b(0);
    out->scale_error(k) = b(1);
    out->offset_m(k) = b(2);
  }
  const double dn = static_cast<double>(n);
  out->ate_rmse_m = std::sqrt(sum_ate / dn);
  out->rmse_after_lead_m = std::sqrt(sum_lead / dn);
  out->rmse_after_scale_m = std::sqrt(sum_scale / dn);
  out->rmse_after_both_m = std::sqrt(sum_both / dn);
  out->poses = err.size();
  return Status::Ok();
}

}  // namespace icgm
