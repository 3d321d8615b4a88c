// icgm_map_eval: loop-closure quality of a saved hybrid map against a ground-truth camera
// trajectory (TUM format). A revisit is a keyframe with an earlier keyframe, at least
// --min-gap-s earlier, within --revisit-m and --revisit-deg (ground truth); a loop link is
// correct when its relative pose agrees with ground truth within --max-error-m / --max-error-deg.
// Prints the share of revisits with a loop link (recall), false loops, and the start-to-end
// error of the keyframe chain.
#include <cmath>
#include <cstdio>
#include <set>

#include "core/dataset/trajectory.h"
#include "core/eval/trajectory_evaluation.h"
#include "core/map/map_store.h"
#include "tools/cli_args.h"

namespace {

constexpr char kUsage[] =
    "usage: icgm_map_eval --map MAP.db --gt GT.txt [--revisit-m 0.5] [--revisit-deg 30]\n"
    "                     [--min-gap-s 30] [--max-error-m 0.1] [--max-error-deg 5]\n";

double Deg(const icgm::Pose3& p) { return icgm::RotationAngleRad(p) * 180.0 / M_PI; }

}  // namespace

int main(int argc, char** argv) {
  std::string map_path, gt_path;
  double revisit_m = 0.5, revisit_deg = 30, min_gap_s = 30, max_err_m = 0.1, max_err_deg = 5;
  try {
    icgm::tools::CliArgs args(
        argc, argv,
        {"map", "gt", "revisit-m", "revisit-deg", "min-gap-s", "max-error-m", "max-error-deg"},
        {"help"});
    if (args.Has("help")) {
      std::printf("%s", kUsage);
      return 0;
    }
    map_path = args.Require("map");
    gt_path = args.Require("gt");
    revisit_m = args.GetDouble("revisit-m", revisit_m);
    revisit_deg = args.GetDouble("revisit-deg", revisit_deg);
    min_gap_s = args.GetDouble("min-gap-s", min_gap_s);
    max_err_m = args.GetDouble("max-error-m", max_err_m);
    max_err_deg = args.GetDouble("max-error-deg", max_err_deg);
  } catch (const std::invalid_argument& e) {
    std::fprintf(stderr, "icgm_map_eval: %s\n%s", e.what(), kUsage);
    return 2;
  }
  try {
    const icgm::HybridMap map = icgm::LoadMap(map_path);
    const icgm::Trajectory gt = icgm::ReadTumTrajectory(gt_path);
    std::vector<std::optional<icgm::Pose3>> truth(map.size());
    for (int i = 0; i < map.size(); ++i) truth[i] = icgm::PoseAt(gt, map.keyframe(i).stamp, 0.1);
    std::set<int> closed;
    int loops = 0, false_loops = 0, far_loops = 0;
    for (const icgm::Link& l : map.links()) {
      if (l.type != icgm::LinkType::kLoopClosure) continue;
      ++loops;
      if (!truth[l.from_id] || !truth[l.to_id]) continue;
      const icgm::Pose3 err =
          icgm::Between(icgm::Between(*truth[l.from_id], *truth[l.to_id]), l.relative_pose);
      if (icgm::TranslationNorm(err) > max_err_m || Deg(err) > max_err_deg) ++false_loops;
      // Joins keyframes that are not at the same place by the revisit criterion.
      const icgm::Pose3 apart = icgm::Between(*truth[l.from_id], *truth[l.to_id]);
      if (icgm::TranslationNorm(apart) > revisit_m || Deg(apart) > revisit_deg) ++far_loops;
      closed.insert(std::max(l.from_id, l.to_id));
    }
    int revisits = 0, found = 0;
    for (int i = 0; i < map.size(); ++i) {
      if (!truth[i]) continue;
      bool revisit = false;
      for (int j = 0; j < i && !revisit; ++j) {
        if (!truth[j] ||
            icgm::DurationSeconds(map.keyframe(i).stamp, map.keyframe(j).stamp) < min_gap_s) {
          continue;
        }
        const icgm::Pose3 rel = icgm::Between(*truth[j], *truth[i]);
        revisit = icgm::TranslationNorm(rel) <= revisit_m && Deg(rel) <= revisit_deg;
      }
      revisits += revisit;
      found += revisit && closed.count(i);
    }
    std::printf("keyframes %d, loop links %d, false loops %d (error > %.2f m or %.1f deg)\n",
                map.size(), loops, false_loops, max_err_m, max_err_deg);
    std::printf("loop links between keyframes more than %.2f m or %.0f deg apart: %d\n", revisit_m,
                revisit_deg, far_loops);
    std::printf(
        "revisits %d (within %.2f m and %.0f deg of a keyframe >= %.0f s older), with a "
        "loop link %d: recall %.1f%%\n",
        revisits, revisit_m, revisit_deg, min_gap_s, found,
        revisits ? 100.0 * found / revisits : 0.0);
    if (map.size() > 1 && truth.front() && truth.back()) {
      const icgm::Pose3 est =
          icgm::Between(map.keyframes().front().global_pose, map.keyframes().back().global_pose);
      const icgm::Pose3 tru = icgm::Between(*truth.front(), *truth.back());
      const icgm::Pose3 err = icgm::Between(tru, est);
      std::printf("start-to-end error %.4f m, %.2f deg (true start-to-end distance %.3f m)\n",
                  icgm::TranslationNorm(err), Deg(err), icgm::TranslationNorm(tru));
    }
    // Keyframe poses L_n against ground truth (SE(3) alignment).
    icgm::Trajectory keyframes;
    for (const icgm::Keyframe& kf : map.keyframes())
      keyframes.push_back({kf.stamp, kf.global_pose});
    icgm::TrajectoryEvalOptions eval_options;
    eval_options.max_dt_s = 0.1;
    icgm::TrajectoryEvaluation eval;
    if (icgm::EvaluateTrajectory(gt, keyframes, eval_options, &eval).ok()) {
      std::printf("keyframe ATE rmse %.4f m, max %.4f m (%zu keyframes)\n", eval.ate.rmse,
                  eval.ate.max, eval.num_associated());
    }
  } catch (const icgm::LoadError& e) {
    std::fprintf(stderr, "icgm_map_eval: %s\n", e.what());
    return 1;
  }
  return 0;
}
