#include "core/optimization/bundle_adjustment.h"

#include <cmath>
#include <memory>

#include "core/common/option_reader.h"

#ifdef ICGM_HAVE_CERES
#include "core/optimization/ceres_costs.h"
#include "core/optimization/pixel_observation_cost.h"
#endif

namespace icgm {

void ReadOptions(const OptionReader& reader, BundleAdjustmentOptions* o) {
  reader.Read("max_iterations", &o->max_iterations, 1, 10000);
  reader.Read("max_solver_time_s", &o->max_solver_time_s, 0.0, 3600.0);
  reader.Read("huber_sigma", &o->huber_sigma, 0.0, 100.0);
  reader.Read("use_depth", &o->use_depth);
  reader.Read("depth_sigma_m", &o->depth_sigma_m, 1e-6, 1.0);
  reader.Read("depth_sigma_per_m2", &o->depth_sigma_per_m2, 0.0, 1.0);
  reader.Read("outlier_chi2", &o->outlier_chi2, 0.1, 1e6);
  reader.Read("outlier_rounds", &o->outlier_rounds, 0, 10);
  reader.Read("min_observations", &o->min_observations, 2, 1000);
}

namespace {

Status CheckProblem(const BaProblem& p) {
  const int cameras = static_cast<int>(p.world_camera.size());
  const int points = static_cast<int>(p.points_world.size());
  if (!p.fixed.empty() && static_cast<int>(p.fixed.size()) != cameras) {
    return Status::Error("bundle adjustment: " + std::to_string(p.fixed.size()) +
                         " fixed flags for " + std::to_string(cameras) + " cameras");
  }
  for (const BaObservation& o : p.observations) {
    if (o.camera < 0 || o.camera >= cameras || o.point < 0 || o.point >= points) {
      return Status::Error("bundle adjustment: observation of point " + std::to_string(o.point) +
                           " by camera " + std::to_string(o.camera) + " out of range");
    }
    if (!o.pixel_px.allFinite() || !(o.pixel_sigma_px > 0)) {
      return Status::Error("bundle adjustment: non-finite pixel or non-positive sigma");
    }
  }
  for (const BaRelativePose& r : p.priors) {
    if (r.from < 0 || r.from >= cameras || r.to < 0 || r.to >= cameras || r.from == r.to) {
      return Status::Error("bundle adjustment: prior " + std::to_string(r.from) + " -> " +
                           std::to_string(r.to) + " out of range");
    }
  }
  return Status::Ok();
}

}  // namespace

Status BundleAdjust(const CameraIntrinsics& intrinsics, const BundleAdjustmentOptions& options,
                    BaProblem* problem, BaSummary* summary, std::vector<uint8_t>* inlier) {
  if (summary) *summary = BaSummary();
  if (inlier) inlier->assign(problem->observations.size(), 0);
  const Status valid = CheckProblem(*problem);
  if (!valid.ok()) return valid;
  if (!intrinsics.Valid()) return Status::Error("bundle adjustment: invalid intrinsics");
#ifndef ICGM_HAVE_CERES
  (void)options;
  return Status::Error("bundle adjustment: built without Ceres");
#else
  const size_t n_cam = problem->world_camera.size();
  const size_t n_pts = problem->points_world.size();
  std::vector<Vec3> t(n_cam);
  std::vector<Quat> q(n_cam);
  for (size_t i = 0; i < n_cam; ++i) {
    t[i] = problem->world_camera[i].translation();
    q[i] = Quat(problem->world_camera[i].linear()).normalized();
  }
  std::vector<Vec3> x = problem->points_world;

  const auto depth_sigma = [&](double d) {
    return options.depth_sigma_m + options.depth_sigma_per_m2 * d * d;
  };
  const auto has_depth = [&](const BaObservation& o) {
    return options.use_depth && std::isfinite(o.depth_m) && o.depth_m > 0;
  };
  // Whitened squared error of one observation at the current estimate.
  const auto chi2 = [&](const BaObservation& o) {
    const Vec3 pc = q[o.camera].conjugate() * (x[o.point] - t[o.camera]);
    if (pc.z() < 1e-3) return std::numeric_limits<double>::infinity();
    const Eigen::Vector2d e = (intrinsics.Project(pc) - o.pixel_px) / o.pixel_sigma_px;
    double c = e.squaredNorm();
    if (has_depth(o)) c += std::pow((pc.z() - o.depth_m) / depth_sigma(o.depth_m), 2);
    return c;
  };
  const auto dof = [&](const BaObservation& o) { return has_depth(o) ? 3 : 2; };

  // Square-root information of the priors, the same every round.
  std::vector<Mat6> prior_sqrt_info;
  prior_sqrt_info.reserve(problem->priors.size());
  for (const BaRelativePose& r : problem->priors) {
    const Eigen::LLT<Mat6> llt(0.5 * (r.information + r.information.transpose()));
    if (llt.info() != Eigen::Success) {
      return Status::Error("bundle adjustment: prior information not positive definite");
    }
    prior_sqrt_info.push_back(llt.matrixU());
  }

  std::vector<uint8_t> active(problem->observations.size(), 1);
  for (size_t k = 0; k < active.size(); ++k) {
    if (!std::isfinite(chi2(problem->observations[k]))) active[k] = 0;
  }
  // Active observations per point, and whether observation k takes part (active, and its point
  // seen often enough).
  const auto count_active = [&]() {
    std::vector<int> count(n_pts, 0);
    for (size_t k = 0; k < active.size(); ++k) {
      if (active[k]) ++count[problem->observations[k].point];
    }
    return count;
  };
  const auto used = [&](size_t k, const std::vector<int>& count) {
    return active[k] && count[problem->observations[k].point] >= options.min_observations;
  };
  BaSummary s;
  double first_rms = -1.0;
  std::string report;
  int iterations = 0;
  double time_s = 0.0;
  for (int round = 0; round <= options.outlier_rounds; ++round) {
    const std::vector<int> count = count_active();
    std::unique_ptr<ceres::LossFunction> loss;
    if (options.huber_sigma > 0) loss = std::make_unique<ceres::HuberLoss>(options.huber_sigma);
    ceres::Problem::Options po;
    po.loss_function_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
    ceres::Problem cp(po);
    int used_obs = 0;
    double sum_sq = 0.0;
    int residuals = 0;
    for (size_t k = 0; k < active.size(); ++k) {
      if (!used(k, count)) continue;
      const BaObservation& o = problem->observations[k];
      const bool d = has_depth(o);
      // Without depth: the same cost and derivatives, computed on their nonzero entries only.
      ceres::CostFunction* cost =
          options.use_depth
              ? RgbdObservationError::Create(intrinsics, o.pixel_px, o.pixel_sigma_px,
                                             d ? o.depth_m : 0.0, d ? depth_sigma(o.depth_m) : 0.0)
              : new PixelObservationCost(intrinsics, o.pixel_px, o.pixel_sigma_px);
      cp.AddResidualBlock(cost, loss.get(), t[o.camera].data(), q[o.camera].coeffs().data(),
                          x[o.point].data());
      sum_sq += chi2(o);
      residuals += dof(o);
      ++used_obs;
    }
    if (used_obs == 0) return Status::Error("bundle adjustment: no point seen by two cameras");
    if (first_rms < 0) first_rms = std::sqrt(sum_sq / residuals);
    for (size_t p = 0; p < problem->priors.size(); ++p) {
      const BaRelativePose& r = problem->priors[p];
      cp.AddResidualBlock(RelativePoseError::Create(r.measured, prior_sqrt_info[p]), nullptr,
                          t[r.from].data(), q[r.from].coeffs().data(), t[r.to].data(),
                          q[r.to].coeffs().data());
    }
    int cameras = 0, fixed = 0;
    for (size_t i = 0; i < n_cam; ++i) {
      if (!cp.HasParameterBlock(t[i].data())) continue;
      ++cameras;
      cp.SetManifold(q[i].coeffs().data(), new ceres::EigenQuaternionManifold);
      if (!problem->fixed.empty() && problem->fixed[i]) {
        cp.SetParameterBlockConstant(t[i].data());
        cp.SetParameterBlockConstant(q[i].coeffs().data());
        ++fixed;
      }
    }
    if (fixed == 0) {
      // Gauge: hold the first camera in the problem.
      for (size_t i = 0; i < n_cam; ++i) {
        if (!cp.HasParameterBlock(t[i].data())) continue;
        cp.SetParameterBlockConstant(t[i].data());
        cp.SetParameterBlockConstant(q[i].coeffs().data());
        ++fixed;
        break;
      }
    }
    ceres::Solver::Options so;
    so.linear_solver_type = ceres::SPARSE_SCHUR;
    so.max_num_iterations = options.max_iterations;
    if (options.max_solver_time_s > 0.0) so.max_solver_time_in_seconds = options.max_solver_time_s;
    so.num_threads = 1;
    ceres::Solver::Summary cs;
    ceres::Solve(so, &cp, &cs);
    if (!cs.IsSolutionUsable()) {
      return Status::Error("bundle adjustment: solver failed: " + cs.message);
    }
    iterations += static_cast<int>(cs.iterations.size()) - 1;
    time_s += cs.total_time_in_seconds;
    report = cs.BriefReport();
    s.cameras = cameras;
    s.fixed_cameras = fixed;
    s.observations = used_obs;
    int points = 0;
    for (size_t p = 0; p < n_pts; ++p) points += count[p] >= options.min_observations;
    s.points = points;
    // Final residual and outliers at the new estimate.
    sum_sq = 0.0;
    residuals = 0;
    int outliers = 0;
    for (size_t k = 0; k < active.size(); ++k) {
      if (!used(k, count)) continue;
      const BaObservation& o = problem->observations[k];
      const double c = chi2(o);
      if (c > options.outlier_chi2) {
        ++outliers;
        if (round < options.outlier_rounds) active[k] = 0;
        continue;
      }
      sum_sq += c;
      residuals += dof(o);
    }
    s.outliers = outliers;
    s.final_rms = residuals > 0 ? std::sqrt(sum_sq / residuals) : 0.0;
    if (outliers == 0) break;
  }
  s.initial_rms = first_rms;
  s.iterations = iterations;
  s.time_s = time_s;
  s.report = report;
  for (size_t i = 0; i < n_cam; ++i) problem->world_camera[i] = MakePose(t[i], q[i].normalized());
  problem->points_world = x;
  if (inlier) {
    const std::vector<int> count = count_active();
    for (size_t k = 0; k < active.size(); ++k) {
      (*inlier)[k] = used(k, count) && chi2(problem->observations[k]) <= options.outlier_chi2;
    }
  }
  if (summary) *summary = s;
  return Status::Ok();
#endif
}

}  // namespace icgm
