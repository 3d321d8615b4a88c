#include "core/odometry/pose_window.h"

#include <algorithm>
#include <cmath>

#include <Eigen/Dense>

#include "core/common/option_reader.h"
#include "core/registration/pose_refinement.h"

namespace icgm {

namespace {

using WindowVec6 = Eigen::Matrix<double, 6, 1>;
using WindowMat6 = Eigen::Matrix<double, 6, 6>;

// Derivatives of s = LogSE3(A^-1 B) (decoupled twist) with respect to right perturbations of A
// and of B, to first order (the rotation vector's own Jacobian taken as identity: the steps
// and residuals here are small rotations).
void StepJacobians(const Pose3& relative, WindowMat6* d_first, WindowMat6* d_second) {
  d_first->setZero();
  d_first->block<3, 3>(0, 0) = -Eigen::Matrix3d::Identity();
  d_first->block<3, 3>(0, 3) = Skew(relative.translation());
  d_first->block<3, 3>(3, 3) = -Eigen::Matrix3d::Identity();
  d_second->setZero();
  d_second->block<3, 3>(0, 0) = relative.linear();
  d_second->block<3, 3>(3, 3) = Eigen::Matrix3d::Identity();
}

}  // namespace

void ReadOptions(const OptionReader& reader, PoseWindowOptions* options) {
  reader.Read("window_frames", &options->frames, 0, 1000);
  reader.Read("window_acceleration_sigma_m", &options->acceleration_sigma_m, 1e-6, 10.0);
  reader.Read("window_acceleration_sigma_deg", &options->acceleration_sigma_deg, 1e-4, 180.0);
  reader.Read("window_robust_sigmas", &options->robust_sigmas, 0.0, 1e6);
  reader.Read("window_acceleration_robust_sigmas", &options->acceleration_robust_sigmas, 0.0,
              1e6);
  reader.Read("window_iterations", &options->iterations, 1, 100);
}

PoseWindow::PoseWindow(const PoseWindowOptions& options, double max_gap_s)
    : options_(options), max_gap_s_(max_gap_s) {}

Pose3 PoseWindow::Add(Time stamp, const std::vector<PoseLink>& links, const Pose3& initial) {
  if (!frames_.empty() && (stamp <= frames_.back().stamp ||
                           DurationSeconds(stamp, frames_.back().stamp) > max_gap_s_)) {
    frames_.clear();
  }
  Entry entry;
  entry.stamp = stamp;
  entry.pose = initial;
  for (const PoseLink& link : links) {
    Eigen::LDLT<Mat6> ldlt(link.covariance);
    if (link.covariance.allFinite() && ldlt.info() == Eigen::Success && ldlt.isPositive() &&
        link.odom_camera.matrix().allFinite()) {
      entry.links.push_back(link);
    }
  }
  entry.fixed = entry.links.empty();
  frames_.push_back(std::move(entry));
  const size_t max_frames = static_cast<size_t>(std::max(options_.frames, 1));
  while (frames_.size() > max_frames) frames_.pop_front();
  last_weights_.assign(frames_.back().links.size(), 1.0);
  if (!frames_.back().fixed && frames_.size() >= 2) Optimise();
  return frames_.back().pose;
}

void PoseWindow::Optimise() {
  const int n = static_cast<int>(frames_.size());
  // Free poses: all but the oldest and those without links.
  std::vector<int> var(n, -1);
  int m = 0;
  for (int i = 1; i < n; ++i) {
    if (!frames_[i].fixed) var[i] = m++;
  }
  if (m == 0) return;
  // Whitening of the links (L^T L = information) and of the constant-velocity term.
  std::vector<std::vector<WindowMat6>> whiten(n);
  for (int i = 0; i < n; ++i) {
    for (const PoseLink& link : frames_[i].links) {
      const WindowMat6 info = link.covariance.ldlt().solve(WindowMat6::Identity());
      const WindowMat6 sym = 0.5 * (info + info.transpose());
      Eigen::LLT<WindowMat6> llt(sym);
      whiten[i].push_back(llt.info() == Eigen::Success ? WindowMat6(llt.matrixU())
                                                       : WindowMat6::Zero());
    }
  }
  WindowVec6 accel_scale;
  const double st = 1.0 / options_.acceleration_sigma_m;
  const double sr = 1.0 / (options_.acceleration_sigma_deg * M_PI / 180.0);
  accel_scale << st, st, st, sr, sr, sr;
  double mean_dt = DurationSeconds(frames_.back().stamp, frames_.front().stamp) / (n - 1);
  if (!(mean_dt > 0.0)) return;
  const double c2 = options_.robust_sigmas * options_.robust_sigmas;
  const auto cauchy_weight = [&](double squared) {
    return options_.robust_sigmas > 0.0 ? 1.0 / (1.0 + squared / c2) : 1.0;
  };
  const double a2 = options_.acceleration_robust_sigmas * options_.acceleration_robust_sigmas;
  const auto accel_weight = [&](double squared) {
    return options_.acceleration_robust_sigmas > 0.0 ? 1.0 / (1.0 + squared / a2) : 1.0;
  };

  for (int iteration = 0; iteration < options_.iterations; ++iteration) {
    Eigen::MatrixXd h = Eigen::MatrixXd::Zero(6 * m, 6 * m);
    Eigen::VectorXd g = Eigen::VectorXd::Zero(6 * m);
    // Links: unary terms on their frame's pose.
    for (int i = 0; i < n; ++i) {
      if (var[i] < 0) continue;
      for (size_t k = 0; k < frames_[i].links.size(); ++k) {
        const Pose3 error = Between(frames_[i].links[k].odom_camera, frames_[i].pose);
        const WindowVec6 r = whiten[i][k] * LogSE3(error);
        WindowMat6 unused, d_pose;
        StepJacobians(error, &unused, &d_pose);
        const WindowMat6 j = whiten[i][k] * d_pose;
        const double w = cauchy_weight(r.squaredNorm());
        if (i == n - 1) last_weights_[k] = w;
        h.block<6, 6>(6 * var[i], 6 * var[i]) += w * j.transpose() * j;
        g.segment<6>(6 * var[i]) += w * j.transpose() * r;
      }
    }
    // Constant velocity: triples of consecutive frames.
    for (int b = 1; b + 1 < n; ++b) {
      const int idx[3] = {b - 1, b, b + 1};
      const Pose3 step1 = Between(frames_[b - 1].pose, frames_[b].pose);
      const Pose3 step2 = Between(frames_[b].pose, frames_[b + 1].pose);
      const double dt1 = DurationSeconds(frames_[b].stamp, frames_[b - 1].stamp);
      const double dt2 = DurationSeconds(frames_[b + 1].stamp, frames_[b].stamp);
      const WindowVec6 r =
          accel_scale.cwiseProduct((LogSE3(step2) / dt2 - LogSE3(step1) / dt1) * mean_dt);
      WindowMat6 d1a, d1b, d2b, d2c;
      StepJacobians(step1, &d1a, &d1b);
      StepJacobians(step2, &d2b, &d2c);
      const auto scale = accel_scale.asDiagonal();
      WindowMat6 j[3];
      j[0] = scale * (-(mean_dt / dt1) * d1a);
      j[1] = scale * (mean_dt * (d2b / dt2 - d1b / dt1));
      j[2] = scale * ((mean_dt / dt2) * d2c);
      const double w = accel_weight(r.squaredNorm());
      for (int p = 0; p < 3; ++p) {
        if (var[idx[p]] < 0) continue;
        g.segment<6>(6 * var[idx[p]]) += w * j[p].transpose() * r;
        for (int q = 0; q < 3; ++q) {
          if (var[idx[q]] < 0) continue;
          h.block<6, 6>(6 * var[idx[p]], 6 * var[idx[q]]) += w * j[p].transpose() * j[q];
        }
      }
    }
    h.diagonal().array() += 1e-9;
    const Eigen::VectorXd delta = h.ldlt().solve(-g);
    if (!delta.allFinite()) return;
    for (int i = 0; i < n; ++i) {
      if (var[i] < 0) continue;
      frames_[i].pose = Orthonormalized(frames_[i].pose * ExpSE3(delta.segment<6>(6 * var[i])));
    }
    if (delta.lpNorm<Eigen::Infinity>() < 1e-7) break;
  }
}

}  // namespace icgm
