// icgm_slam_map: builds a hybrid map offline from a TUM RGB-D folder with the SLAM system
// (core/slam/slam_system.h: front end + hybrid map with loop closure) and saves it; optionally
// adds the recording as a new session to an existing map.
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <memory>
#include <string>

#include "core/common/progress_bar.h"
#include "core/dataset/camera_options.h"
#include "core/dataset/tum_dataset.h"
#include "core/eval/trajectory_evaluation.h"
#include "core/map/map_store.h"
#include "core/slam/slam_runner.h"
#include "core/slam/slam_system.h"
#include "tools/cli_args.h"

namespace {

constexpr char kUsage[] =
    "usage: icgm_slam_map --tum DIR --map OUT.db --trajectory OUT.txt\n"
    "                     [--camera config/camera/tum_fr1.yaml] [--config-dir config]\n"
    "                     [--merge-into EXISTING.db] [--max-frames N] [--localization]\n"
    "                     [--no-loop-closure] [--keyframes KF.txt] [--odometry ODOM.txt]\n"
    "  Runs the front end and the hybrid map (loop closure, eq. 6.2/6.4) over a TUM RGB-D\n"
    "  folder, saves the map (SQLite) and the camera trajectory in the map frame (TUM format).\n"
    "  --merge-into adds the recording as a new session to EXISTING.db (written to --map).\n"
    "  --localization locates the recording in the map of --merge-into, which it never\n"
    "  writes: --map must be another file.\n"
    "  Prints loop closures, keyframes, per-stage timing, memory per keyframe and, when the\n"
    "  folder has ground truth, the ATE of the odometry, the map trajectory and the keyframes.\n";
constexpr icgm::tools::ToolInfo kTool{"icgm_slam_map", kUsage};

int UsageError(const std::string& message) { return icgm::tools::UsageError(kTool, message); }

// Resident set size of this process in KiB (Linux), 0 when unknown.
long ResidentKiB() {
  std::ifstream status("/proc/self/status");
  std::string key;
  while (status >> key) {
    if (key == "VmRSS:") {
      long kib = 0;
      status >> kib;
      return kib;
    }
    status.ignore(1 << 16, '\n');
  }
  return 0;
}

void PrintAte(const char* name, const icgm::Trajectory& gt, const icgm::Trajectory& estimate) {
  icgm::TrajectoryEvaluation ev;
  const icgm::Status s = icgm::EvaluateTrajectory(gt, estimate, icgm::TrajectoryEvalOptions(), &ev);
  if (!s.ok()) {
    std::printf("ATE %-12s not available: %s\n", name, s.reason().c_str());
    return;
  }
  std::printf("ATE %-12s rmse %.4f m, mean %.4f m, max %.4f m (%zu poses)\n", name, ev.ate.rmse,
              ev.ate.mean, ev.ate.max, ev.ate.count);
}

}  // namespace

int main(int argc, char** argv) {
  std::string tum_dir, camera_path, config_dir, map_path, trajectory_path, merge_path,
      keyframes_path, odometry_path;
  int max_frames = 0;
  bool localization = false, no_loop_closure = false;
  try {
    const icgm::tools::CliArgs args(argc, argv,
                                    {"tum", "camera", "config-dir", "map", "trajectory",
                                     "merge-into", "max-frames", "keyframes", "odometry"},
                                    {"localization", "no-loop-closure"});
    if (args.help()) return icgm::tools::PrintUsage(kTool);
    if (!args.positional().empty())
      return UsageError("unexpected argument '" + args.positional().front() + "'");
    tum_dir = args.Require("tum");
    map_path = args.Require("map");
    trajectory_path = args.Require("trajectory");
    config_dir = args.Get("config-dir", ICGM_CONFIG_DIR);
    camera_path = args.Get("camera", config_dir + "/camera/tum_fr1.yaml");
    merge_path = args.Get("merge-into");
    keyframes_path = args.Get("keyframes");
    odometry_path = args.Get("odometry");
    max_frames = args.GetInt("max-frames", 0);
    if (args.Has("max-frames") && max_frames < 1) return UsageError("--max-frames must be >= 1");
    localization = args.Has("localization");
    no_loop_closure = args.Has("no-loop-closure");
    namespace fs = std::filesystem;
    if (localization && fs::exists(map_path) && fs::exists(merge_path) &&
        fs::equivalent(map_path, merge_path)) {
      return UsageError("--localization never writes the learned map: give --map another file");
    }
  } catch (const std::invalid_argument& e) {
    return UsageError(e.what());
  }

  std::shared_ptr<icgm::TumDataset> dataset;
  icgm::SlamOptions options;
  try {
    icgm::TumSlamInput input = icgm::LoadTumSlamInput(config_dir, tum_dir, camera_path);
    options = std::move(input.options);
    dataset = std::move(input.dataset);
  } catch (const icgm::LoadError& e) {
    std::fprintf(stderr, "icgm_slam_map: %s\n", e.what());
    return 1;
  }
  // Checked before processing: a long run must not end without its map or trajectories.
  const icgm::Status writable = icgm::CheckMapWritable(map_path);
  if (!writable.ok()) return icgm::tools::Failure(kTool, writable.reason());
  const std::string problem =
      icgm::tools::OutputFolderProblem({trajectory_path, keyframes_path, odometry_path});
  if (!problem.empty()) return icgm::tools::Failure(kTool, problem);
  options.loop_closure = !no_loop_closure;
  const long rss_start_kib = ResidentKiB();
  icgm::SlamSystem slam(options, dataset->intrinsics());
  if (!merge_path.empty()) {
    const icgm::Status loaded = slam.Load(merge_path, false);
    if (!loaded.ok()) {
      std::fprintf(stderr, "icgm_slam_map: %s\n", loaded.reason().c_str());
      return 1;
    }
    if (!slam.load_note().empty()) {
      std::fprintf(stderr, "icgm_slam_map: warning: %s\n", slam.load_note().c_str());
    }
    std::printf("merging into %s: %d keyframes in %zu sessions\n", merge_path.c_str(),
                slam.map().size(), slam.map().sessions().size());
  }
  if (localization) slam.SetMode(icgm::MapMode::kLocalization);

  icgm::SlamRunOptions run;
  run.max_frames = static_cast<size_t>(max_frames);
  const size_t total =
      max_frames > 0 ? std::min<size_t>(dataset->size(), max_frames) : dataset->size();
  icgm::ProgressBar progress(total, "hybrid SLAM");
  run.on_frame = [&progress](size_t done, const icgm::SlamInputFrame&,
                            const icgm::SlamFrameResult&) { progress.Update(done); };
  const icgm::SlamRunReport report = icgm::RunSlam(&slam, icgm::TumFrameSource(dataset), run);
  progress.Finish(report.input_error.empty() ? total : report.frames);
  if (report.frames == 0) {
    std::fprintf(stderr, "icgm_slam_map: no frames processed %s\n", report.input_error.c_str());
    return 1;
  }

  std::printf("%s", icgm::FormatSlamReport(report, slam).c_str());
  // The process growth includes the front end's recent keyframes with their images; the map's
  // own share is the "map memory" line above.
  std::printf(
      "process memory: %.1f MiB resident (+%.1f MiB during the run incl. front-end images, "
      "%.1f KiB per map keyframe)\n",
      ResidentKiB() / 1024.0, (ResidentKiB() - rss_start_kib) / 1024.0,
      report.map_keyframes
          ? static_cast<double>(ResidentKiB() - rss_start_kib) / report.map_keyframes
          : 0.0);
  for (const icgm::LoopClosureEvent& e : slam.loop_closures()) {
    std::string candidates;
    for (int c : e.candidate_ids) candidates += (candidates.empty() ? "" : ",") + std::to_string(c);
    const icgm::Pose3 moved = icgm::Between(e.pose_before, e.pose_after);
    std::printf(
        "loop closure: frame %zu keyframe %d <- [%s], %d registrations, "
        "diff %.4f m %.3f deg, moved %.4f m\n",
        e.frame_index, e.keyframe_id, candidates.c_str(), e.registrations,
        icgm::TranslationNorm(e.delta_pose_diff),
        icgm::RotationAngleRad(e.delta_pose_diff) * 180.0 / M_PI, icgm::TranslationNorm(moved));
  }
  if (dataset->has_groundtruth()) {
    PrintAte("odometry", dataset->groundtruth(), slam.OdomTrajectory());
    PrintAte("map", dataset->groundtruth(), slam.MapTrajectory());
    PrintAte("keyframes", dataset->groundtruth(), slam.KeyframeTrajectory());
  }

  try {
    icgm::WriteTumTrajectory(trajectory_path, slam.MapTrajectory());
    if (!keyframes_path.empty())
      icgm::WriteTumTrajectory(keyframes_path, slam.KeyframeTrajectory());
    if (!odometry_path.empty()) icgm::WriteTumTrajectory(odometry_path, slam.OdomTrajectory());
  } catch (const icgm::LoadError& e) {
    std::fprintf(stderr, "icgm_slam_map: %s\n", e.what());
    return 1;
  }
  // SaveMap, not Save: in localization it refuses the learned map's file.
  const icgm::Status saved = slam.SaveMap(map_path, /*refine=*/false);
  if (!saved.ok()) {
    std::fprintf(stderr, "icgm_slam_map: %s\n", saved.reason().c_str());
    return 1;
  }
  std::printf("map written to %s (%d keyframes, %zu sessions), trajectory to %s\n",
              map_path.c_str(), slam.map().size(), slam.map().sessions().size(),
              trajectory_path.c_str());
  if (!report.input_error.empty()) {
    // The outputs cover the frames before the failure only: not a success.
    return icgm::tools::Failure(kTool,
                                icgm::tools::InputEndedEarly(report.frames, report.input_error));
  }
  return 0;
}
