#include "core/map/pose_graph_optimizer.h"

#include <memory>
#include <string>
#include <vector>

#ifdef ICGM_HAVE_CERES
#include "core/optimization/ceres_costs.h"
#endif

namespace icgm {

#ifdef ICGM_HAVE_CERES
namespace {

// Upper factor U with U^T U = information; fails when information is not positive definite.
bool SqrtInformation(const Mat6& information, Mat6* sqrt_information) {
  const Eigen::LLT<Mat6> llt(0.5 * (information + information.transpose()));
  if (llt.info() != Eigen::Success) return false;
  *sqrt_information = llt.matrixU();
  return true;
}

}  // namespace
#endif  // ICGM_HAVE_CERES

bool PoseGraphOptimizer::Available() {
#ifdef ICGM_HAVE_CERES
  return true;
#else
  return false;
#endif
}

Status PoseGraphOptimizer::Optimize(const HybridMap& map, std::vector<Pose3>* poses,
                                    PoseGraphSummary* summary,
                                    const std::vector<bool>* extra_fixed) const {
  const int n = map.size();
  poses->clear();
  for (const auto& kf : map.keyframes()) poses->push_back(kf.global_pose);
  if (summary) *summary = PoseGraphSummary();
  if (extra_fixed && static_cast<int>(extra_fixed->size()) != n) {
    return Status::Error("pose graph: extra_fixed has " + std::to_string(extra_fixed->size()) +
                         " entries for " + std::to_string(n) + " keyframes");
  }
#ifndef ICGM_HAVE_CERES
  return Status::Error("pose graph: built without Ceres");
#else
  if (n == 0) return Status::Error("pose graph: empty map");
  // Parameter blocks, indexed by keyframe id: translation (3) and quaternion x, y, z, w (4).
  std::vector<Vec3> t(static_cast<size_t>(n));
  std::vector<Quat> q(static_cast<size_t>(n));
  for (int i = 0; i < n; ++i) {
    t[i] = (*poses)[i].translation();
    q[i] = Quat((*poses)[i].linear()).normalized();
  }

  // One loss object shared by all loop links, owned here rather than by the problem.
  std::unique_ptr<ceres::LossFunction> loss;
  switch (options_.loss) {
    case RobustLoss::kHuber:
      loss = std::make_unique<ceres::HuberLoss>(options_.loss_scale_sigma);
      break;
    case RobustLoss::kCauchy:
      loss = std::make_unique<ceres::CauchyLoss>(options_.loss_scale_sigma);
      break;
    case RobustLoss::kNone:
      break;
  }
  ceres::Problem::Options problem_options;
  problem_options.loss_function_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
  ceres::Problem problem(problem_options);
  int blocks = 0;
  for (const Link& link : map.links()) {
    if (link.from_id < 0 || link.from_id >= n || link.to_id < 0 || link.to_id >= n ||
        link.from_id == link.to_id) {
      return Status::Error("pose graph: link " + std::to_string(link.from_id) + " -> " +
                           std::to_string(link.to_id) + " has invalid keyframe ids");
    }
    Mat6 sqrt_information;
    if (!SqrtInformation(link.information, &sqrt_information)) {
      return Status::Error("pose graph: information of link " + std::to_string(link.from_id) +
                           " -> " + std::to_string(link.to_id) + " is not positive definite");
    }
    ceres::LossFunction* link_loss = link.type == LinkType::kLoopClosure ? loss.get() : nullptr;
    problem.AddResidualBlock(RelativePoseError::Create(link.relative_pose, sqrt_information), link_loss,
                             t[link.from_id].data(), q[link.from_id].coeffs().data(),
                             t[link.to_id].data(), q[link.to_id].coeffs().data());
    ++blocks;
  }
  if (blocks == 0) return Status::Error("pose graph: no links");

  // Keyframes without links are not in the problem; the others get the quaternion manifold.
  int fixed = 0;
  for (int i = 0; i < n; ++i) {
    if (!problem.HasParameterBlock(t[i].data())) continue;
    problem.SetManifold(q[i].coeffs().data(), new ceres::EigenQuaternionManifold);
    const Keyframe& kf = map.keyframe(i);
    const bool session_start = kf.previous_id < 0 && (options_.fix_session_starts || i == 0);
    if (i == 0 || session_start || (extra_fixed && (*extra_fixed)[i])) {
      problem.SetParameterBlockConstant(t[i].data());
      problem.SetParameterBlockConstant(q[i].coeffs().data());
      ++fixed;
    }
  }
  if (fixed == 0) {
    // The first keyframe has no link; hold the first keyframe that has one.
    for (int i = 0; i < n && fixed == 0; ++i) {
      if (!problem.HasParameterBlock(t[i].data())) continue;
      problem.SetParameterBlockConstant(t[i].data());
      problem.SetParameterBlockConstant(q[i].coeffs().data());
      ++fixed;
    }
  }

  ceres::Solver::Options solver_options;
  solver_options.linear_solver_type = ceres::SPARSE_NORMAL_CHOLESKY;
  solver_options.max_num_iterations = options_.max_iterations;
  solver_options.max_solver_time_in_seconds = options_.max_solver_time_s;
  solver_options.function_tolerance = options_.function_tolerance;
  solver_options.num_threads = 1;
  ceres::Solver::Summary ceres_summary;
  ceres::Solve(solver_options, &problem, &ceres_summary);

  if (summary) {
    summary->initial_cost = ceres_summary.initial_cost;
    summary->final_cost = ceres_summary.final_cost;
    summary->iterations = static_cast<int>(ceres_summary.iterations.size()) - 1;
    summary->time_s = ceres_summary.total_time_in_seconds;
    summary->residual_blocks = blocks;
    summary->fixed_keyframes = fixed;
    summary->report = ceres_summary.BriefReport();
  }
  if (!ceres_summary.IsSolutionUsable()) {
    return Status::Error("pose graph: solver failed: " + ceres_summary.message);
  }
  if (ceres_summary.termination_type != ceres::CONVERGENCE) {
    return Status::Error("pose graph: did not converge in " +
                         std::to_string(options_.max_iterations) + " iterations (" +
                         ceres_summary.message + ")");
  }
  for (int i = 0; i < n; ++i) (*poses)[i] = MakePose(t[i], q[i].normalized());
  return Status::Ok();
#endif
}

}  // namespace icgm
