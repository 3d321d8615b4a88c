#include "core/mono/mono_evaluation.h"

#include <algorithm>
#include <cmath>
#include <tuple>

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

Status BreakDownMonoMaps(const Trajectory& groundtruth, const std::vector<Trajectory>& maps,
                         double max_dt_s, MonoMapBreakdown* out) {
  *out = MonoMapBreakdown();
  // Every pose with its map, in stamp order; a repeated stamp keeps the later map's pose.
  std::vector<std::tuple<Time, size_t, Pose3>> all;
  for (size_t m = 0; m < maps.size(); ++m) {
    for (const StampedPose& p : maps[m]) all.emplace_back(p.stamp, m, p.pose);
  }
  std::stable_sort(all.begin(), all.end(), [](const auto& a, const auto& b) {
    return std::tie(std::get<0>(a), std::get<1>(a)) < std::tie(std::get<0>(b), std::get<1>(b));
  });
  Trajectory whole;
  std::vector<size_t> map_of;
  for (const auto& [stamp, m, pose] : all) {
    if (!whole.empty() && whole.back().stamp == stamp) {
      whole.back().pose = pose;
      map_of.back() = m;
    } else {
      whole.push_back({stamp, pose});
      map_of.push_back(m);
    }
  }
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
  return rescaled_error(carry, &out->carry_fixed_percent);
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
