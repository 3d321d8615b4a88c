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
#include "core/eval/error_stats.h"
#include "core/eval/trajectory_evaluation.h"
#include "core/geometry/absolute_orientation.h"
#include "core/map/map_store.h"
#include "tools/cli_args.h"

namespace {

constexpr char kUsage[] =
    "usage: icgm_map_eval --map MAP.db --gt GT.txt [--revisit-m 0.5] [--revisit-deg 30]\n"
    "                     [--min-gap-s 30] [--max-error-m 0.1] [--max-error-deg 5]\n"
    "                     [--links]\n"
    "  --links: relative-pose errors of the odometry, wheel-odometry and loop-closure links\n"
    "  against ground truth, each loop link beside the odometry chain over the same keyframes.\n";
constexpr icgm::tools::ToolInfo kTool{"icgm_map_eval", kUsage};

double Deg(const icgm::Pose3& p) { return icgm::RotationAngleRad(p) * 180.0 / M_PI; }

// Translation sigma in metres that a link's information claims (mean of the three axes).
double LinkSigmaM(const icgm::Link& l) {
  const double info = l.information.block<3, 3>(0, 0).trace() / 3.0;
  return info > 0.0 ? 1.0 / std::sqrt(info) : 0.0;
}

// The rotation X between the ground truth's body frame and the camera frame that best explains
// the odometry links' translations (t_truth ~ X t_link); a few degrees of hand-eye rotation
// in the ground truth make every link look wrong in proportion to its length.
icgm::Pose3 EstimateBodyFromCamera(const icgm::HybridMap& map,
                                   const std::vector<std::optional<icgm::Pose3>>& truth) {
  std::vector<Eigen::Vector3d> src, dst;
  for (const icgm::Link& l : map.links()) {
    if (l.type != icgm::LinkType::kOdometry || !truth[l.from_id] || !truth[l.to_id]) continue;
    const icgm::Pose3 tru = icgm::Between(*truth[l.from_id], *truth[l.to_id]);
    for (double sign : {1.0, -1.0}) {  // symmetric pairs: a rotation without translation
      src.push_back(sign * l.relative_pose.translation());
      dst.push_back(sign * tru.translation());
    }
  }
  icgm::SimilarityTransform x;
  if (src.size() < 6 || !icgm::HornAlign(src, dst, false, &x).ok()) return icgm::Pose3::Identity();
  icgm::Pose3 out = icgm::Pose3::Identity();
  out.linear() = x.rotation;
  return out;
}

// Errors of the links' relative poses against ground truth: odometry links summarized, each
// loop link listed with the error of the odometry chain over the same keyframe span and of the
// map's current poses, so one sees whether loop links are better or worse than what they correct.
// With `hand_eye`, the ground truth is first rotated by EstimateBodyFromCamera.
void PrintLinkErrors(const icgm::HybridMap& map,
                     const std::vector<std::optional<icgm::Pose3>>& truth_in, bool hand_eye) {
  std::vector<std::optional<icgm::Pose3>> truth = truth_in;
  if (hand_eye) {
    const icgm::Pose3 x = EstimateBodyFromCamera(map, truth);
    std::printf("ground-truth body to camera rotation from the odometry links: %.2f deg\n",
                Deg(x));
    for (auto& t : truth) if (t) t = *t * x;
  }
  std::vector<double> odo_m, odo_deg, wheel_m, wheel_deg, loop_m, loop_deg, chain_m, chain_deg;
  // odometry[i]: the odometry link into keyframe i (from its previous keyframe).
  std::vector<const icgm::Link*> odometry(map.size(), nullptr);
  for (const icgm::Link& l : map.links()) {
    if (l.type == icgm::LinkType::kOdometry && l.to_id >= 0 && l.to_id < map.size()) {
      odometry[l.to_id] = &l;
    }
  }
  std::printf("loop links: from to  span  dist_m | link err mm deg | chain err mm deg | "
              "map err mm deg | inliers sigma_mm\n");
  for (const icgm::Link& l : map.links()) {
    if (!truth[l.from_id] || !truth[l.to_id]) continue;
    const icgm::Pose3 tru = icgm::Between(*truth[l.from_id], *truth[l.to_id]);
    const icgm::Pose3 err = icgm::Between(tru, l.relative_pose);
    if (l.type == icgm::LinkType::kOdometry) {
      odo_m.push_back(icgm::TranslationNorm(err));
      odo_deg.push_back(Deg(err));
      continue;
    }
    if (l.type == icgm::LinkType::kWheelOdometry) {
      wheel_m.push_back(icgm::TranslationNorm(err));
      wheel_deg.push_back(Deg(err));
      continue;
    }
    loop_m.push_back(icgm::TranslationNorm(err));
    loop_deg.push_back(Deg(err));
    // Odometry chain from the lower to the higher id, when one session links them.
    const int lo = std::min(l.from_id, l.to_id), hi = std::max(l.from_id, l.to_id);
    icgm::Pose3 chain = icgm::Pose3::Identity();
    bool chained = true;
    for (int i = lo + 1; i <= hi && chained; ++i) {
      chained = odometry[i] && odometry[i]->from_id == i - 1;
      if (chained) chain = chain * odometry[i]->relative_pose;
    }
    if (l.from_id > l.to_id) chain = chain.inverse();
    const icgm::Pose3 chain_err = icgm::Between(tru, chain);
    const icgm::Pose3 map_err = icgm::Between(
        tru, icgm::Between(map.keyframe(l.from_id).global_pose, map.keyframe(l.to_id).global_pose));
    if (chained) {
      chain_m.push_back(icgm::TranslationNorm(chain_err));
      chain_deg.push_back(Deg(chain_err));
    }
    std::printf("  %4d %4d %4d  %.3f | %6.1f %5.2f | %6.1f %5.2f | %6.1f %5.2f | %4d %5.1f\n",
                l.from_id, l.to_id, hi - lo, icgm::TranslationNorm(tru),
                1e3 * icgm::TranslationNorm(err), Deg(err),
                chained ? 1e3 * icgm::TranslationNorm(chain_err) : NAN,
                chained ? Deg(chain_err) : NAN, 1e3 * icgm::TranslationNorm(map_err), Deg(map_err),
                l.inliers, 1e3 * LinkSigmaM(l));
  }
  const auto print = [](const char* name, const std::vector<double>& m,
                        const std::vector<double>& deg) {
    const icgm::ErrorStats sm = icgm::ComputeErrorStats(m), sd = icgm::ComputeErrorStats(deg);
    std::printf("%-24s %3zu: translation rmse %.1f mm, median %.1f, max %.1f; rotation rmse "
                "%.2f deg, median %.2f, max %.2f\n",
                name, sm.count, 1e3 * sm.rmse, 1e3 * sm.median, 1e3 * sm.max, sd.rmse, sd.median,
                sd.max);
  };
  print("odometry links", odo_m, odo_deg);
  if (!wheel_m.empty()) print("wheel-odometry links", wheel_m, wheel_deg);
  print("loop links", loop_m, loop_deg);
  print("odometry chains of loops", chain_m, chain_deg);
}

}  // namespace

int main(int argc, char** argv) {
  std::string map_path, gt_path;
  bool link_errors = false;
  double revisit_m = 0.5, revisit_deg = 30, min_gap_s = 30, max_err_m = 0.1, max_err_deg = 5;
  try {
    icgm::tools::CliArgs args(
        argc, argv,
        {"map", "gt", "revisit-m", "revisit-deg", "min-gap-s", "max-error-m", "max-error-deg"},
        {"links"});
    if (args.help()) return icgm::tools::PrintUsage(kTool);
    link_errors = args.Has("links");
    map_path = args.Require("map");
    gt_path = args.Require("gt");
    revisit_m = args.GetDouble("revisit-m", revisit_m);
    revisit_deg = args.GetDouble("revisit-deg", revisit_deg);
    min_gap_s = args.GetDouble("min-gap-s", min_gap_s);
    max_err_m = args.GetDouble("max-error-m", max_err_m);
    max_err_deg = args.GetDouble("max-error-deg", max_err_deg);
  } catch (const std::invalid_argument& e) {
    return icgm::tools::UsageError(kTool, e.what());
  }
  try {
    std::string note;
    const icgm::HybridMap map = icgm::LoadMap(map_path, &note);
    if (!note.empty()) std::fprintf(stderr, "%s: warning: %s\n", kTool.name, note.c_str());
    const icgm::Trajectory gt = icgm::ReadTumTrajectory(gt_path);
    std::vector<std::optional<icgm::Pose3>> truth(map.size());
    for (int i = 0; i < map.size(); ++i) truth[i] = icgm::PoseAt(gt, map.keyframe(i).stamp, 0.1);
    std::set<int> closed;
    int loops = 0, false_loops = 0, far_loops = 0;
    for (const icgm::Link& l : map.links()) {
      if (l.type != icgm::LinkType::kLoopClosure) continue;
      ++loops;
      if (!truth[l.from_id] || !truth[l.to_id]) continue;
      const icgm::Pose3 apart = icgm::Between(*truth[l.from_id], *truth[l.to_id]);
      const icgm::Pose3 err = icgm::Between(apart, l.relative_pose);
      if (icgm::TranslationNorm(err) > max_err_m || Deg(err) > max_err_deg) ++false_loops;
      // Joins keyframes that are not at the same place by the revisit criterion.
      if (icgm::TranslationNorm(apart) > revisit_m || Deg(apart) > revisit_deg) ++far_loops;
      closed.insert(std::max(l.from_id, l.to_id));
    }
    if (link_errors) {
      PrintLinkErrors(map, truth, false);
      PrintLinkErrors(map, truth, true);
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
