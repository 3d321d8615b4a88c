#include "core/mono/mono_evaluation.h"

#include <algorithm>
#include <cmath>
#include <tuple>

#include <Eigen/Geometry>
#include <Eigen/SVD>

namespace icgm {

double PathLengthM(const std::vector<Pose3>& poses) {
  double length = 0.0;
  for (size_t i = 1; i < poses.size(); ++i) {
    length += (poses[i].translation() - poses[i - 1].translation()).norm();
  }
  return length;
}

Status EvaluateMonoTrajectory(const Trajectory& groundtruth, const Trajectory& estimate,
                              double max_dt_s, MonoEvaluation* out) {
  TrajectoryEvalOptions options;
  options.max_dt_s = max_dt_s;
  options.estimate_scale = true;
  const Status s = EvaluateTrajectory(groundtruth, estimate, options, &out->evaluation);
  if (!s.ok()) return s;
  out->distance_m = PathLengthM(out->evaluation.groundtruth);
  if (!(out->distance_m > 1e-9)) return Status::Error("the ground truth does not move");
  out->error_percent = 100.0 * out->evaluation.ate.rmse / out->distance_m;
  out->scale = out->evaluation.alignment.scale;
  return Status::Ok();
}

std::vector<double> DefaultSegmentFractions() { return {0.1, 0.2, 0.3, 0.4, 0.5}; }

namespace {

// Sums of the segment error's parts (MonoSegmentErrors).
struct SegmentParts {
  double rotation_deg = 0.0, direction_deg = 0.0, length_only_percent = 0.0;
  size_t segments = 0, directions = 0;
  std::vector<double> length_ratios;

  void Finish(MonoSegmentErrors* out) {
    out->rotation_error_deg = segments > 0 ? rotation_deg / segments : 0.0;
    out->length_only_percent = segments > 0 ? length_only_percent / segments : 0.0;
    out->direction_error_deg = directions > 0 ? direction_deg / directions : 0.0;
    if (!length_ratios.empty()) {
      std::nth_element(length_ratios.begin(), length_ratios.begin() + length_ratios.size() / 2,
                       length_ratios.end());
      out->length_ratio_median = length_ratios[length_ratios.size() / 2];
    }
  }
};

void AddSegmentParts(const Pose3& truth_ij, const Pose3& estimate_ij, double path_m,
                     SegmentParts* parts) {
  const Eigen::Vector3d t = truth_ij.translation(), e = estimate_ij.translation();
  parts->rotation_deg += RotationAngleRad(truth_ij.inverse() * estimate_ij) * 180.0 / M_PI;
  parts->length_only_percent += 100.0 * std::abs(e.norm() - t.norm()) / path_m;
  ++parts->segments;
  if (t.norm() > 1e-12) parts->length_ratios.push_back(e.norm() / t.norm());
  if (t.norm() > 1e-12 && e.norm() > 1e-12) {
    const double c = std::clamp(t.dot(e) / (t.norm() * e.norm()), -1.0, 1.0);
    parts->direction_deg += std::acos(c) * 180.0 / M_PI;
    ++parts->directions;
  }
}

}  // namespace

Status EvaluateMonoSegments(const TrajectoryEvaluation& aligned,
                            const std::vector<double>& length_fractions, MonoSegmentErrors* out) {
  *out = MonoSegmentErrors();
  const std::vector<Pose3>& truth = aligned.groundtruth;
  const std::vector<Pose3>& estimate = aligned.aligned_estimate;
  // Ground-truth path length up to each associated pose.
  std::vector<double> path(truth.size(), 0.0);
  for (size_t i = 1; i < truth.size(); ++i) {
    path[i] = path[i - 1] + (truth[i].translation() - truth[i - 1].translation()).norm();
  }
  const double total = path.empty() ? 0.0 : path.back();
  if (!(total > 1e-9)) return Status::Error("segments: the ground truth does not move");
  SegmentParts parts;
  for (const double fraction : length_fractions) {
    if (!(fraction > 0.0 && fraction < 1.0)) {
      return Status::Error("segments: a length fraction must lie in (0, 1)");
    }
    MonoSegmentLength l;
    l.fraction = fraction;
    l.length_m = fraction * total;
    double sum = 0.0;
    for (size_t i = 0, j = 0; i < truth.size(); ++i) {
      j = std::max(j, i + 1);
      while (j < truth.size() && path[j] - path[i] < l.length_m) ++j;
      if (j >= truth.size()) break;
      const Pose3 truth_ij = truth[i].inverse() * truth[j];
      const Pose3 estimate_ij = estimate[i].inverse() * estimate[j];
      const Pose3 error = truth_ij.inverse() * estimate_ij;
      const double percent = 100.0 * error.translation().norm() / (path[j] - path[i]);
      out->errors_percent.push_back(percent);
      AddSegmentParts(truth_ij, estimate_ij, path[j] - path[i], &parts);
      out->standing_still_percent +=
          100.0 * (truth[j].translation() - truth[i].translation()).norm() / (path[j] - path[i]);
      sum += percent;
      ++l.segments;
    }
    l.mean_percent = l.segments > 0 ? sum / l.segments : 0.0;
    out->lengths.push_back(l);
  }
  if (out->errors_percent.empty()) return Status::Error("segments: no segment fits the run");
  std::vector<double> sorted = out->errors_percent;
  double sum = 0.0;
  for (const double e : sorted) sum += e;
  out->mean_percent = sum / sorted.size();
  out->standing_still_percent /= sorted.size();
  parts.Finish(out);
  std::nth_element(sorted.begin(), sorted.begin() + sorted.size() / 2, sorted.end());
  out->median_percent = sorted[sorted.size() / 2];
  return Status::Ok();
}

namespace {

// Every pose of the maps in stamp order, with its map; a repeated stamp keeps the later map's.
Trajectory Assemble(const std::vector<Trajectory>& maps, std::vector<size_t>* map_of) {
  std::vector<std::tuple<Time, size_t, Pose3>> all;
  for (size_t m = 0; m < maps.size(); ++m) {
    for (const StampedPose& p : maps[m]) all.emplace_back(p.stamp, m, p.pose);
  }
  std::stable_sort(all.begin(), all.end(), [](const auto& a, const auto& b) {
    return std::tie(std::get<0>(a), std::get<1>(a)) < std::tie(std::get<0>(b), std::get<1>(b));
  });
  Trajectory whole;
  map_of->clear();
  for (const auto& [stamp, m, pose] : all) {
    if (!whole.empty() && whole.back().stamp == stamp) {
      whole.back().pose = pose;
      map_of->back() = m;
    } else {
      whole.push_back({stamp, pose});
      map_of->push_back(m);
    }
  }
  return whole;
}

SimilarityTransform Inverse(const SimilarityTransform& a) {
  SimilarityTransform b;
  b.scale = 1.0 / a.scale;
  b.rotation = a.rotation.transpose();
  b.translation = -(b.rotation * a.translation) / a.scale;
  return b;
}

// a after b.
SimilarityTransform Compose(const SimilarityTransform& a, const SimilarityTransform& b) {
  SimilarityTransform c;
  c.scale = a.scale * b.scale;
  c.rotation = a.rotation * b.rotation;
  c.translation = a.scale * (a.rotation * b.translation) + a.translation;
  return c;
}

double AngleDeg(const Eigen::Matrix3d& r) {
  return Eigen::AngleAxisd(r).angle() * 180.0 / M_PI;
}

// The ground-truth pose nearest `stamp` within max_dt_s (`groundtruth` sorted by stamp).
std::optional<Pose3> TruthAt(const Trajectory& groundtruth, Time stamp, double max_dt_s) {
  const auto it = std::lower_bound(
      groundtruth.begin(), groundtruth.end(), stamp,
      [](const StampedPose& p, Time t) { return p.stamp < t; });
  std::optional<Pose3> best;
  double best_dt = max_dt_s;
  for (auto c = it == groundtruth.begin() ? it : std::prev(it);
       c != groundtruth.end() && c <= it; ++c) {
    const double dt = std::abs(DurationSeconds(c->stamp, stamp));
    if (dt <= best_dt) {
      best_dt = dt;
      best = c->pose;
    }
  }
  return best;
}

// A short stretch aligned with the ground truth: the Sim(3) scale of its positions, the rotation
// averaged over its orientations (R_gt R_est^T projected onto SO(3)), the translation meeting
// the centroids; with `scale` that scale instead of the Sim(3)'s. nullopt with fewer than kMinPoses associated poses or no Sim(3).
std::optional<SimilarityTransform> AlignStretch(const Trajectory& groundtruth,
                                                const Trajectory& stretch, double max_dt_s,
                                                std::optional<double> scale = std::nullopt) {
  if (stretch.size() < MonoJoinFigures::kMinPoses) return std::nullopt;
  MonoEvaluation e;
  if (!EvaluateMonoTrajectory(groundtruth, stretch, max_dt_s, &e).ok()) return std::nullopt;
  const TrajectoryEvaluation& t = e.evaluation;
  if (t.num_associated() < MonoJoinFigures::kMinPoses) return std::nullopt;
  const SimilarityTransform back = Inverse(t.alignment);
  Eigen::Matrix3d sum = Eigen::Matrix3d::Zero();
  Eigen::Vector3d mean_gt = Eigen::Vector3d::Zero(), mean_est = Eigen::Vector3d::Zero();
  for (size_t i = 0; i < t.num_associated(); ++i) {
    const Pose3 est = ApplySimilarity(back, t.aligned_estimate[i]);
    sum += t.groundtruth[i].linear() * est.linear().transpose();
    mean_gt += t.groundtruth[i].translation();
    mean_est += est.translation();
  }
  const double n = static_cast<double>(t.num_associated());
  Eigen::JacobiSVD<Eigen::Matrix3d> svd(sum, Eigen::ComputeFullU | Eigen::ComputeFullV);
  Eigen::Matrix3d d = Eigen::Matrix3d::Identity();
  if ((svd.matrixU() * svd.matrixV().transpose()).determinant() < 0.0) d(2, 2) = -1.0;
  SimilarityTransform a;
  a.scale = scale.value_or(t.alignment.scale);
  a.rotation = svd.matrixU() * d * svd.matrixV().transpose();
  a.translation = mean_gt / n - a.scale * (a.rotation * mean_est / n);
  return a;
}

}  // namespace

Status BreakDownMonoMaps(const Trajectory& groundtruth_in, const std::vector<Trajectory>& maps,
                         double max_dt_s, MonoMapBreakdown* out) {
  *out = MonoMapBreakdown();
  Trajectory groundtruth = groundtruth_in;
  SortByStamp(&groundtruth);
  std::vector<size_t> map_of;
  const Trajectory whole = Assemble(maps, &map_of);
  MonoEvaluation eval;
  if (const Status s = EvaluateMonoTrajectory(groundtruth, whole, max_dt_s, &eval); !s.ok()) {
    return s;
  }
  out->whole_percent = eval.error_percent;
  // Each map on its own.
  double sum_sq = 0.0, distance = 0.0;
  size_t poses = 0;
  for (const Trajectory& map : maps) {
    MonoMapFigures f;
    f.poses = map.size();
    MonoEvaluation m;
    if (map.size() >= 10 && EvaluateMonoTrajectory(groundtruth, map, max_dt_s, &m).ok()) {
      f.aligned = true;
      f.poses = m.evaluation.num_associated();
      f.scale = m.scale;
      f.ate_rmse_m = m.evaluation.ate.rmse;
      f.distance_m = m.distance_m;
      if (map.size() >= MonoMapFigures::kEdgePoses) {
        const Trajectory first(map.begin(), map.begin() + MonoMapFigures::kEdgePoses);
        const Trajectory last(map.end() - MonoMapFigures::kEdgePoses, map.end());
        MonoEvaluation edge;
        if (EvaluateMonoTrajectory(groundtruth, first, max_dt_s, &edge).ok()) {
          f.scale_first = edge.scale;
        }
        if (EvaluateMonoTrajectory(groundtruth, last, max_dt_s, &edge).ok()) {
          f.scale_last = edge.scale;
        }
      }
      sum_sq += f.poses * f.ate_rmse_m * f.ate_rmse_m;
      poses += f.poses;
      distance += f.distance_m;
      ++out->aligned_maps;
    }
    out->maps.push_back(f);
  }
  if (poses == 0 || !(distance > 0.0)) return Status::Error("no map aligns on its own");
  out->per_map_percent = 100.0 * std::sqrt(sum_sq / poses) / distance;
  // Every step rescaled by its map's scale over the first aligned map's; a map that does not
  // align keeps the factor of the map before it.
  double reference = 0.0;
  for (const MonoMapFigures& f : out->maps) {
    if (f.aligned) {
      reference = f.scale;
      break;
    }
  }
  std::vector<double> factor(maps.size(), 1.0), carry(maps.size(), 1.0);
  for (size_t m = 0; m < maps.size(); ++m) {
    const MonoMapFigures& f = out->maps[m];
    factor[m] = f.aligned ? f.scale / reference : (m > 0 ? factor[m - 1] : 1.0);
    if (m == 0) continue;
    const MonoMapFigures& before = out->maps[m - 1];
    carry[m] = carry[m - 1];
    if (f.scale_first > 0.0 && before.scale_last > 0.0) {
      carry[m] *= f.scale_first / before.scale_last;
    }
  }
  // A step into a new map (to its reference frame, placed at the last pose of the map before)
  // is in the units of the map it leaves.
  const auto rescaled_error = [&](const std::vector<double>& by, double* percent) {
    Trajectory fixed = whole;
    for (size_t i = 1; i < whole.size(); ++i) {
      fixed[i].pose.translation() =
          fixed[i - 1].pose.translation() +
          by[map_of[i - 1]] * (whole[i].pose.translation() - whole[i - 1].pose.translation());
    }
    MonoEvaluation e;
    const Status s = EvaluateMonoTrajectory(groundtruth, fixed, max_dt_s, &e);
    *percent = e.error_percent;
    return s;
  };
  if (const Status s = rescaled_error(factor, &out->scale_fixed_percent); !s.ok()) return s;
  if (const Status s = rescaled_error(carry, &out->carry_fixed_percent); !s.ok()) return s;
  // The joins: each side aligned on its own; the maps moved so that every join is exact.
  std::vector<Trajectory> joined = maps, rigid = maps;
  SimilarityTransform chain, rigid_chain;  // of the map before (identity for the first)
  for (size_t m = 1; m < maps.size(); ++m) {
    MonoJoinFigures j;
    j.map = m;
    const Trajectory& before = maps[m - 1];
    const Trajectory& after = maps[m];
    if (!before.empty() && !after.empty()) {
      j.gap_s = DurationSeconds(after.front().stamp, before.back().stamp);
      const auto a = TruthAt(groundtruth, before.back().stamp, max_dt_s);
      const auto b = TruthAt(groundtruth, after.front().stamp, max_dt_s);
      if (a && b) {
        j.gap_motion_m = (b->translation() - a->translation()).norm();
        j.gap_rotation_deg = AngleDeg(a->linear().transpose() * b->linear());
      }
    }
    const size_t k = MonoJoinFigures::kJoinPoses;
    const Trajectory last(before.size() > k ? before.end() - k : before.begin(), before.end());
    const Trajectory first(after.begin(), after.size() > k ? after.begin() + k : after.end());
    const auto align_before = AlignStretch(groundtruth, last, max_dt_s);
    const auto align_after = AlignStretch(groundtruth, first, max_dt_s);
    if (align_before && align_after) {
      j.aligned = true;
      j.scale_ratio = align_after->scale / align_before->scale;
      j.rotation_deg = AngleDeg(align_before->rotation.transpose() * align_after->rotation);
      const Eigen::Vector3d p = after.front().pose.translation();
      j.position_m = (align_after->Apply(p) - align_before->Apply(p)).norm();
      chain = Compose(chain, Compose(Inverse(*align_before), *align_after));
      if (const auto same_scale =
              AlignStretch(groundtruth, first, max_dt_s, align_before->scale)) {
        rigid_chain = Compose(rigid_chain, Compose(Inverse(*align_before), *same_scale));
      }
    }
    for (StampedPose& p : joined[m]) p.pose = ApplySimilarity(chain, p.pose);
    for (StampedPose& p : rigid[m]) p.pose = ApplySimilarity(rigid_chain, p.pose);
    out->joins.push_back(j);
  }
  std::vector<size_t> joined_map_of;
  MonoEvaluation e;
  if (const Status s = EvaluateMonoTrajectory(groundtruth, Assemble(joined, &joined_map_of),
                                              max_dt_s, &e);
      !s.ok()) {
    return s;
  }
  out->joins_fixed_percent = e.error_percent;
  if (const Status s =
          EvaluateMonoTrajectory(groundtruth, Assemble(rigid, &joined_map_of), max_dt_s, &e);
      !s.ok()) {
    return s;
  }
  out->joins_rigid_fixed_percent = e.error_percent;
  return Status::Ok();
}

std::optional<double> MapScaleFromDepth(const cv::Mat& depth_m,
                                        const std::vector<Eigen::Vector2d>& pixels,
                                        const std::vector<double>& map_depths) {
  if (depth_m.empty() || depth_m.type() != CV_32FC1) return std::nullopt;
  std::vector<double> ratios;
  for (size_t i = 0; i < pixels.size() && i < map_depths.size(); ++i) {
    const int u = static_cast<int>(std::lround(pixels[i].x()));
    const int v = static_cast<int>(std::lround(pixels[i].y()));
    if (u < 0 || v < 0 || u >= depth_m.cols || v >= depth_m.rows) continue;
    const float z = depth_m.at<float>(v, u);
    if (std::isfinite(z) && z > 0.0f && map_depths[i] > 1e-9) ratios.push_back(z / map_depths[i]);
  }
  if (ratios.size() < 10) return std::nullopt;
  std::nth_element(ratios.begin(), ratios.begin() + ratios.size() / 2, ratios.end());
  return ratios[ratios.size() / 2];
}

}  // namespace icgm
