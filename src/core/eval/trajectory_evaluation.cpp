#include "core/eval/trajectory_evaluation.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>

#include "core/dataset/stamp_association.h"

namespace icgm {

Pose3 ApplySimilarity(const SimilarityTransform& s, const Pose3& pose) {
  Pose3 out = Pose3::Identity();
  out.linear() = s.rotation * pose.linear();
  out.translation() = s.Apply(pose.translation());
  return out;
}

namespace {

// Rotation angle in [0, pi] via the quaternion, 2 atan2(|v|, |w|): accurate near identity,
// where acos((trace - 1) / 2) loses half the digits (~1e-8 rad floor).
double AngleRad(const Pose3& p) {
  const Quat q(p.linear());
  return 2.0 * std::atan2(q.vec().norm(), std::abs(q.w()));
}

void ComputeRpe(const TrajectoryEvaluation& ev, double delta_s, std::vector<double>* trans,
                std::vector<double>* rot_deg) {
  const auto& st = ev.stamps;
  size_t j = 0;
  for (size_t i = 0; i < st.size(); ++i) {
    j = std::max(j, i + 1);
    while (j < st.size() && DurationSeconds(st[j], st[i]) < delta_s) ++j;
    if (j >= st.size()) break;
    const double dt = DurationSeconds(st[j], st[i]);
    const Pose3 gt_rel = Between(ev.groundtruth[i], ev.groundtruth[j]);
    const Pose3 est_rel = Between(ev.aligned_estimate[i], ev.aligned_estimate[j]);
    const Pose3 err = Between(gt_rel, est_rel);
    trans->push_back(TranslationNorm(err) / dt);
    rot_deg->push_back(AngleRad(err) * 180.0 / M_PI / dt);
  }
}

}  // namespace

Status EvaluateTrajectory(const Trajectory& groundtruth, const Trajectory& estimate,
                          const TrajectoryEvalOptions& options, TrajectoryEvaluation* out) {
  if (!(options.max_dt_s >= 0.0) || !std::isfinite(options.max_dt_s)) {
    return Status::Error("evaluation: max_dt_s must be a finite value >= 0");
  }
  if (!(options.rpe_delta_s > 0.0) || !std::isfinite(options.rpe_delta_s)) {
    return Status::Error("evaluation: rpe_delta_s must be a finite value > 0");
  }
  Trajectory gt = groundtruth;
  Trajectory est = estimate;
  SortByStamp(&gt);
  SortByStamp(&est);
  const auto pairs = AssociateStamps(Stamps(est), Stamps(gt), options.max_dt_s);
  if (pairs.size() < 3) {
    char window[32];
    std::snprintf(window, sizeof(window), "%.3f", options.max_dt_s);
    return Status::Error("evaluation: only " + std::to_string(pairs.size()) +
                         " estimate poses have a ground-truth pose within " + window +
                         " s (need >= 3)");
  }

  TrajectoryEvaluation ev;
  ev.num_groundtruth = gt.size();
  ev.num_estimate = est.size();
  std::vector<Eigen::Vector3d> src, dst;
  for (const auto& [ie, ig] : pairs) {
    ev.stamps.push_back(est[ie].stamp);
    ev.groundtruth.push_back(gt[ig].pose);
    src.push_back(est[ie].pose.translation());
    dst.push_back(gt[ig].pose.translation());
  }
  const Status aligned = HornAlign(src, dst, options.estimate_scale, &ev.alignment);
  if (!aligned.ok()) return Status::Error("evaluation: cannot align: " + aligned.reason());

  for (size_t k = 0; k < pairs.size(); ++k) {
    ev.aligned_estimate.push_back(ApplySimilarity(ev.alignment, est[pairs[k].first].pose));
    ev.ate_m.push_back(
        (ev.groundtruth[k].translation() - ev.aligned_estimate[k].translation()).norm());
  }
  ev.ate = ComputeErrorStats(ev.ate_m);
  std::vector<double> rpe_t, rpe_r;
  ComputeRpe(ev, options.rpe_delta_s, &rpe_t, &rpe_r);
  ev.rpe_translation_m_per_s = ComputeErrorStats(rpe_t);
  ev.rpe_rotation_deg_per_s = ComputeErrorStats(rpe_r);
  *out = std::move(ev);
  return Status::Ok();
}

}  // namespace icgm
