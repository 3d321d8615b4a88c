// icgm_slam_benchmark: what the hybrid map adds to the RGB-D front end on a TUM RGB-D sequence
// with ground truth. One SlamSystem run per alpha_mapping value (eq. 6.4); each run reports the
// ATE of the front-end odometry alone, of the map trajectory (every frame, final keyframe poses)
// and of the keyframes, the loop closures, and the loop-closure query time per keyframe. The
// targets (ATE <= --target-ate-m, query p95 <= --target-query-ms) are checked here, not in tests.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <memory>
#include <sstream>
#include <string>
#include <vector>

#include "core/common/progress_bar.h"
#include "core/common/sample_summary.h"
#include "core/dataset/camera_options.h"
#include "core/dataset/tum_dataset.h"
#include "core/eval/trajectory_evaluation.h"
#include "core/slam/slam_runner.h"
#include "core/slam/slam_system.h"
#include "tools/cli_args.h"

namespace {

constexpr char kUsage[] =
    "usage: icgm_slam_benchmark --tum DIR [--camera config/camera/tum_fr1.yaml]\n"
    "                           [--config-dir config] [--max-frames N] [--alpha 0.5,1.0]\n"
    "                           [--target-ate-m 0.012] [--target-query-ms 50]\n"
    "                           [--exclude-recent N] [--min-score S] [--no-loop-closure]\n"
    "                           [--verbose] [--all-features]\n"
    "  --all-features keeps every keypoint with depth in the map, not only the ICGM-robust ones.\n"
    "  --verbose prints each loop-closure hypothesis with its error against ground truth.\n"
    "  --exclude-recent / --min-score override loop_closure.* of map.yaml for experiments.\n";
constexpr icgm::tools::ToolInfo kTool{"icgm_slam_benchmark", kUsage};

int UsageError(const std::string& message) { return icgm::tools::UsageError(kTool, message); }

double AteRmse(const icgm::Trajectory& gt, const icgm::Trajectory& estimate) {
  icgm::TrajectoryEvaluation ev;
  if (!icgm::EvaluateTrajectory(gt, estimate, icgm::TrajectoryEvalOptions(), &ev).ok()) return -1;
  return ev.ate.rmse;
}

using icgm::Percentile;

double Mean(const std::vector<double>& v) {
  double s = 0;
  for (double x : v) s += x;
  return v.empty() ? 0.0 : s / v.size();
}

struct RunRow {
  double alpha = 0;
  double ate_odometry = 0, ate_map = 0, ate_keyframes = 0;
  size_t keyframes = 0, closures = 0, registrations = 0;
  double query_mean_ms = 0, query_p95_ms = 0, query_max_ms = 0, frame_mean_ms = 0;
};

// Per loop-closure hypothesis: the error of beta against the ground-truth relative pose of the
// two keyframes, and whether it was used.
void DescribeLoopEvidence(const icgm::SlamFrameResult& r, const icgm::HybridMap& map,
                          const icgm::Trajectory& gt, std::vector<std::string>* lines) {
  if (r.keyframe_id < 0) return;
  const auto query_gt = icgm::PoseAt(gt, map.keyframe(r.keyframe_id).stamp);
  for (const icgm::LoopEvidence& e : r.update.loop.evidence) {
    const auto cand_gt = icgm::PoseAt(gt, map.keyframe(e.candidate_id).stamp);
    char line[256];
    if (!query_gt || !cand_gt) continue;
    const icgm::Pose3 beta_true = icgm::Between(*cand_gt, *query_gt);
    const icgm::Pose3 err = icgm::Between(beta_true, e.registration.relative_pose);
    // The same relative pose from the own loop (odometry chain) before the correction.
    const icgm::Pose3 own =
        icgm::Between(map.keyframe(e.candidate_id).global_pose, r.update.pose_before_correction);
    const icgm::Pose3 own_err = icgm::Between(beta_true, own);
    std::snprintf(
        line, sizeof(line),
        "  kf %3d -> %3d: |beta| %.3f m, beta error %.4f m %.3f deg (own loop %.4f m %.3f "
        "deg), %d inliers%s%s\n",
        r.keyframe_id, e.candidate_id, icgm::TranslationNorm(beta_true), icgm::TranslationNorm(err),
        icgm::RotationAngleRad(err) * 180.0 / M_PI, icgm::TranslationNorm(own_err),
        icgm::RotationAngleRad(own_err) * 180.0 / M_PI, e.registration.inliers,
        e.rejected.empty() ? "" : ", rejected: ", e.rejected.c_str());
    lines->push_back(line);
  }
  // The corrected pose against ground truth, both in the first keyframe's frame (the map frame
  // of a fresh single-session run).
  const auto first_gt = icgm::PoseAt(gt, map.keyframe(0).stamp);
  if (r.update.loop_closed && query_gt && first_gt) {
    const icgm::Pose3 truth = icgm::Between(*first_gt, *query_gt);
    char line[160];
    std::snprintf(line, sizeof(line), "  kf %3d pose error %.4f m before, %.4f m after eq. 6.4\n",
                  r.keyframe_id,
                  icgm::TranslationNorm(icgm::Between(truth, r.update.pose_before_correction)),
                  icgm::TranslationNorm(icgm::Between(truth, r.update.pose)));
    lines->push_back(line);
  }
}

}  // namespace

int main(int argc, char** argv) {
  std::string tum_dir, camera_path, config_dir;
  std::vector<double> alphas;
  int max_frames = 0;
  double target_ate_m = 0.012, target_query_ms = 50.0;
  int exclude_recent = -1;
  double min_score = -1.0;
  bool no_loop_closure = false, verbose = false, all_features = false;
  try {
    const icgm::tools::CliArgs args(
        argc, argv,
        {"tum", "camera", "config-dir", "max-frames", "alpha", "target-ate-m", "target-query-ms",
         "exclude-recent", "min-score"},
        {"no-loop-closure", "verbose", "all-features"});
    if (args.help()) return icgm::tools::PrintUsage(kTool);
    tum_dir = args.Require("tum");
    config_dir = args.Get("config-dir", ICGM_CONFIG_DIR);
    camera_path = args.Get("camera", config_dir + "/camera/tum_fr1.yaml");
    max_frames = args.GetInt("max-frames", 0);
    target_ate_m = args.GetDouble("target-ate-m", target_ate_m);
    target_query_ms = args.GetDouble("target-query-ms", target_query_ms);
    exclude_recent = args.GetInt("exclude-recent", -1);
    min_score = args.GetDouble("min-score", -1.0);
    no_loop_closure = args.Has("no-loop-closure");
    verbose = args.Has("verbose");
    all_features = args.Has("all-features");
    std::stringstream list(args.Get("alpha"));
    for (std::string item; std::getline(list, item, ',');) {
      const double a = std::stod(item);
      if (!(a > 0.0 && a <= 1.0)) return UsageError("--alpha values must be in (0, 1]");
      alphas.push_back(a);
    }
  } catch (const std::exception& e) {
    return UsageError(e.what());
  }

  std::shared_ptr<icgm::TumDataset> dataset;
  icgm::SlamOptions options;
  try {
    icgm::TumSlamInput input = icgm::LoadTumSlamInput(config_dir, tum_dir, camera_path);
    options = std::move(input.options);
    dataset = std::move(input.dataset);
  } catch (const icgm::LoadError& e) {
    std::fprintf(stderr, "icgm_slam_benchmark: %s\n", e.what());
    return 1;
  }
  if (!dataset->has_groundtruth()) {
    std::fprintf(stderr, "icgm_slam_benchmark: %s has no groundtruth.txt\n", tum_dir.c_str());
    return 1;
  }
  if (alphas.empty()) alphas.push_back(options.map.loop_closure.alpha_mapping);
  if (exclude_recent >= 0) options.map.loop_closure.exclude_recent_keyframes = exclude_recent;
  if (min_score >= 0.0) options.map.loop_closure.min_score = min_score;
  options.loop_closure = !no_loop_closure;
  options.conversion.robust_only = !all_features;

  std::vector<RunRow> rows;
  std::string ended_early;  // the first run's input error: the figures cover fewer frames
  for (double alpha : alphas) {
    icgm::SlamOptions o = options;
    o.map.loop_closure.alpha_mapping = alpha;
    icgm::SlamSystem slam(o, dataset->intrinsics());
    icgm::SlamRunOptions run;
    run.max_frames = static_cast<size_t>(max_frames);
    const size_t total =
        max_frames > 0 ? std::min<size_t>(dataset->size(), max_frames) : dataset->size();
    icgm::ProgressBar progress(total, "alpha " + std::to_string(alpha).substr(0, 4));
    std::vector<std::string> loop_lines;
    run.on_frame = [&](size_t done, const icgm::SlamInputFrame&, const icgm::SlamFrameResult& r) {
      progress.Update(done);
      if (verbose) DescribeLoopEvidence(r, slam.map(), dataset->groundtruth(), &loop_lines);
    };
    const icgm::SlamRunReport report = icgm::RunSlam(&slam, icgm::TumFrameSource(dataset), run);
    progress.Finish(report.input_error.empty() ? total : report.frames);
    if (!report.input_error.empty() && ended_early.empty()) {
      ended_early = icgm::tools::InputEndedEarly(report.frames, report.input_error);
    }
    for (const std::string& line : loop_lines) std::printf("%s", line.c_str());
    RunRow row;
    row.alpha = alpha;
    row.ate_odometry = AteRmse(dataset->groundtruth(), slam.OdomTrajectory());
    row.ate_map = AteRmse(dataset->groundtruth(), slam.MapTrajectory());
    row.ate_keyframes = AteRmse(dataset->groundtruth(), slam.KeyframeTrajectory());
    row.keyframes = report.map_keyframes;
    row.closures = report.loop_closures;
    row.registrations = report.loop_registrations;
    row.query_mean_ms = Mean(report.times.map_update);
    row.query_p95_ms = Percentile(report.times.map_update, 0.95);
    row.query_max_ms = Percentile(report.times.map_update, 1.0);
    row.frame_mean_ms = Mean(report.times.frame_total);
    rows.push_back(row);
    if (alphas.size() == 1) std::printf("%s", icgm::FormatSlamReport(report, slam).c_str());
  }

  std::printf("\n%zu frames of %s\n",
              max_frames > 0 ? std::min<size_t>(dataset->size(), max_frames) : dataset->size(),
              tum_dir.c_str());
  std::printf("%6s %10s %10s %10s %5s %6s %6s %10s %10s %10s %10s\n", "alpha", "ATE odom",
              "ATE map", "ATE kf", "kf", "loops", "regs", "query ms", "query p95", "query max",
              "frame ms");
  for (const RunRow& r : rows) {
    std::printf("%6.2f %10.4f %10.4f %10.4f %5zu %6zu %6zu %10.2f %10.2f %10.2f %10.2f\n", r.alpha,
                r.ate_odometry, r.ate_map, r.ate_keyframes, r.keyframes, r.closures,
                r.registrations, r.query_mean_ms, r.query_p95_ms, r.query_max_ms, r.frame_mean_ms);
  }
  const RunRow& first = rows.front();
  std::printf("target ATE (map) <= %.4f m: %s (%.4f m; front end alone %.4f m)\n", target_ate_m,
              first.ate_map >= 0 && first.ate_map <= target_ate_m ? "met" : "NOT met",
              first.ate_map, first.ate_odometry);
  std::printf("target loop-closure query p95 <= %.1f ms per keyframe: %s (%.2f ms)\n",
              target_query_ms, first.query_p95_ms <= target_query_ms ? "met" : "NOT met",
              first.query_p95_ms);
  if (!ended_early.empty()) return icgm::tools::Failure(kTool, ended_early);
  return 0;
}
