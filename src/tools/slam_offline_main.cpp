// icgm_slam_offline: runs the RGB-D front end (features -> matching -> ICGM -> registration ->
// fusion, core/odometry/rgbd_frontend.h) over a TUM RGB-D folder, a rosbag or a simulator
// scenario rendered in process, without a ROS master, as fast as it can, and writes the camera
// trajectory in TUM format.
#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <functional>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <time.h>

#include <opencv2/core.hpp>

#include "core/common/option_reader.h"
#include "core/common/progress_bar.h"
#include "core/common/sample_summary.h"
#include "core/dataset/camera_options.h"
#include "core/dataset/trajectory.h"
#include "core/dataset/tum_dataset.h"
#include "core/eval/trajectory_evaluation.h"
#include "core/odometry/rgbd_frontend.h"
#include "core/map/map_options.h"
#include "core/map/map_store.h"
#include "core/slam/slam_system.h"
#include "core/sim/frame_prefetcher.h"
#include "core/sim/sim_export.h"
#include "core/sim/sim_options.h"
#include "core/sim/simulator.h"
#include "tools/cli_args.h"
#include "tools/dynamic_match_stats.h"
#include "tools/first_pose_ate.h"

#ifdef ICGM_WITH_ROS_BRIDGE
#include "ros_bridge/bag_reader.h"
#endif

namespace {

constexpr char kUsage[] =
    "usage: icgm_slam_offline (--tum DIR | --bag FILE | --sim SCENARIO.yaml)\n"
    "                         --trajectory OUT.txt [--gt-out GT.txt] [--sim-seed N]\n"
    "                         [--config odometry.yaml] [--icgm-config icgm.yaml]\n"
    "                         [--camera camera.yaml] [--report DIR] [--no-icgm]\n"
    "                         [--no-wheel-gate] [--extrinsic-from-config | --camera-only]\n"
    "                         [--max-frames N] [--threads 1]\n"
    "                         [--map OUT.db [--map-config map.yaml] [--pose-graph]\n"
    "                          [--refine]]\n"
    "  Runs the RGB-D visual odometry front end offline and writes the camera trajectory\n"
    "  (TUM format). Prints per-stage timing and the share of motion from vision; with\n"
    "  ground truth, also the ATE; with ground-truth dynamic masks (simulator, simulated\n"
    "  bags), the share of registration matches on pedestrians. --sim renders the scenario\n"
    "  in process (camera, wheel odometry and extrinsic from the simulator; --camera is\n"
    "  ignored); --sim-seed replaces the scenario's seed (same scene layout rules, another\n"
    "  world, crowd and odometry noise). --gt-out writes the ground-truth camera trajectory (TUM format).\n"
    "  --report DIR writes frames.csv and summary.txt. --map builds the hybrid map behind the\n"
    "  front end (loop closure, eq. 6.2/6.4), writes the corrected map trajectory and saves the\n"
    "  map (SQLite, atomic) to OUT.db; --pose-graph corrects loops with the Ceres pose-graph\n"
    "  back end instead of the thesis's eq. 6.4 semi-consensus. --refine (or map_refinement:\n"
    "  enabled in the map config) bundle-adjusts the whole map at the end and saves it again.\n"
    "  --no-wheel-gate turns off the vision/wheel consistency gate of the fusion (the thesis's\n"
    "  fusion: vision whenever registration succeeds). With --bag the intrinsics come from\n"
    "  camera_info (a bag without it needs --camera), but an explicit --camera also\n"
    "  sets the depth time offset and correction and the rolling shutter (depth_time_offset_s,\n"
    "  depth_correction, readout_s, first_row_offset_s), which camera_info cannot carry.\n"
    "  A bag with wheel odometry needs the base_link -> camera extrinsic on /tf_static, or\n"
    "  --extrinsic-from-config (fusion.base_to_camera_* of --config), or --camera-only (the\n"
    "  wheels are ignored). A TUM image that cannot be read is skipped with a warning and\n"
    "  counted. --map is checked before processing: a read-only map file is never replaced.\n";
constexpr icgm::tools::ToolInfo kTool{"icgm_slam_offline", kUsage};

int UsageError(const std::string& message) { return icgm::tools::UsageError(kTool, message); }

// One input frame and everything the sources know up front.
struct OfflineFrame {
  icgm::Time stamp;
  cv::Mat bgr;
  cv::Mat depth_m;
  std::optional<icgm::Time> depth_stamp;  // when the depth image was stamped (default: stamp)
  cv::Mat dynamic_mask;  // CV_8UC1, non-zero on pedestrians; empty when the source has none
};

struct SourceInfo {
  icgm::CameraIntrinsics intrinsics;
  icgm::Trajectory groundtruth;     // camera in world, may be empty
  icgm::Trajectory wheel_odometry;  // odom -> base, may be empty
  std::optional<icgm::Pose3> base_to_camera;
  size_t expected_frames = 0;
  // Frames the source skipped because their images could not be read (counted, not fatal).
  std::shared_ptr<size_t> skipped_frames = std::make_shared<size_t>(0);
};

// Yields frames until false; sets *error on failure.
using NextFrame = std::function<bool(OfflineFrame*, std::string* error)>;

NextFrame OpenTum(const std::string& dir, const icgm::CameraIntrinsics& intrinsics,
                  SourceInfo* info) {
  auto dataset = std::make_shared<icgm::TumDataset>(icgm::TumDataset::Open(dir, intrinsics));
  info->intrinsics = dataset->intrinsics();
  info->groundtruth = dataset->groundtruth();
  info->expected_frames = dataset->size();
  auto next = std::make_shared<size_t>(0);
  auto skipped = info->skipped_frames;
  return [dataset, next, skipped](OfflineFrame* f, std::string*) {
    // An unreadable or wrongly sized image skips its frame (warned and counted) rather than
    // ending the run early.
    while (*next < dataset->size()) {
      const size_t i = (*next)++;
      try {
        f->stamp = dataset->frame(i).stamp;
        f->bgr = dataset->LoadBgr(i);
        f->depth_m = dataset->LoadDepthM(i);
        f->depth_stamp = dataset->frame(i).depth_stamp;
        return true;
      } catch (const icgm::LoadError& e) {
        ++*skipped;
        std::fprintf(stderr, "\nicgm_slam_offline: warning: frame %zu skipped: %s\n", i, e.what());
      }
    }
    return false;
  };
}

// The rosbag input: synchronised RGB-D frames, intrinsics, /tf_static extrinsic and wheel
// odometry from the ROS bridge's RgbdBagStream.
// `fallback`: intrinsics for a bag without camera_info (--camera); without it such a bag is an
// error naming the topic.
NextFrame OpenBag(const std::string& path,
                  const std::optional<icgm::CameraIntrinsics>& fallback, SourceInfo* info) {
#ifdef ICGM_WITH_ROS_BRIDGE
  auto reader = std::make_shared<icgm::ros_bridge::BagReader>(path);
  icgm::ros_bridge::RgbdBagTopics topics;
  topics.fallback_intrinsics = fallback;
  std::shared_ptr<icgm::ros_bridge::RgbdBagStream> stream;
  try {
    stream = std::make_shared<icgm::ros_bridge::RgbdBagStream>(*reader, topics);
  } catch (const icgm::LoadError& e) {
    const std::string what = e.what();
    if (fallback || what.find("camera_info") == std::string::npos) throw;
    throw icgm::LoadError(what + " (--camera FILE)");
  }
  info->intrinsics = stream->intrinsics();
  info->groundtruth = stream->ground_truth();
  info->wheel_odometry = stream->wheel_odometry();
  info->base_to_camera = stream->base_to_camera();
  info->expected_frames = stream->expected_frames();
  return [reader, stream](OfflineFrame* f, std::string* error) {
    icgm::ros_bridge::RgbdBagFrame frame;
    if (!stream->Next(&frame)) {
      if (!stream->status().ok()) *error = stream->status().reason();
      return false;
    }
    f->stamp = frame.stamp;
    f->depth_stamp = frame.depth_stamp;
    f->bgr = frame.bgr;
    f->depth_m = frame.depth_m;
    f->dynamic_mask = frame.dynamic_mask;
    return true;
  };
#else
  (void)fallback;
  (void)info;
  throw std::invalid_argument("--bag " + path +
                              ": this build has no ROS bridge (build the catkin package)");
#endif
}

// A simulator scenario rendered in process (rendering overlaps processing on a worker thread):
// the same data icgm_sim would write to a bag, without the bag.
NextFrame OpenSim(const std::string& scenario_path, std::optional<int> seed, SourceInfo* info) {
  icgm::sim::SimOptions sim_options = icgm::sim::LoadSimOptions(scenario_path);
  if (seed) sim_options.seed = *seed;
  auto sim = std::make_shared<icgm::sim::Simulator>(sim_options);
  info->intrinsics = sim->intrinsics();
  info->groundtruth = icgm::sim::CameraGroundTruth(*sim);
  info->wheel_odometry = icgm::sim::WheelOdometryTrajectory(*sim);
  info->base_to_camera = sim->base_to_camera();  // none for a handheld camera
  info->expected_frames = sim->size();
  auto prefetcher = std::make_shared<icgm::sim::FramePrefetcher>(*sim);
  // The prefetcher refers to the simulator: capture both, simulator first to outlive it.
  return [sim, prefetcher](OfflineFrame* f, std::string*) {
    icgm::sim::SimFrame frame;
    if (!prefetcher->Next(&frame)) return false;
    f->stamp = frame.stamp;
    f->bgr = frame.bgr;
    f->depth_m = frame.depth_m;
    f->dynamic_mask = frame.dynamic_mask;
    return true;
  };
}

using icgm::Summarize;
using Summary = icgm::SampleSummary;

// CPU time of the calling thread in ms: with cv::setNumThreads(1) all front-end work runs here,
// so this is the cost on one core regardless of other load on the machine.
double ThreadCpuMs() {
  timespec ts{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
  return ts.tv_sec * 1e3 + ts.tv_nsec * 1e-6;
}


}  // namespace

int main(int argc, char** argv) {
  std::string map_path, map_config_path;
  bool pose_graph = false;
  bool refine = false;
  bool camera_given = false;  // --camera given (else only the fallback for a bag)
  std::string tum_dir, bag_path, sim_path, gt_out_path, trajectory_path, report_dir, config_path, icgm_config_path,
      camera_path;
  int max_frames = -1, threads = 1;
  std::optional<int> sim_seed;
  bool no_icgm = false;
  bool no_wheel_gate = false;
  bool extrinsic_from_config = false, camera_only = false;
  try {
    const icgm::tools::CliArgs args(argc, argv,
                                    {"tum", "bag", "sim", "sim-seed", "gt-out", "config", "icgm-config", "camera", "trajectory",
                                     "report", "max-frames", "threads", "map", "map-config"},
                                    {"no-icgm", "no-wheel-gate", "pose-graph", "refine",
                                     "extrinsic-from-config", "camera-only"});
    if (args.help()) return icgm::tools::PrintUsage(kTool);
    if (!args.positional().empty()) {
      return UsageError("unexpected argument '" + args.positional().front() + "'");
    }
    tum_dir = args.Get("tum");
    bag_path = args.Get("bag");
    sim_path = args.Get("sim");
    if (tum_dir.empty() + bag_path.empty() + sim_path.empty() != 2) {
      return UsageError("give exactly one of --tum, --bag, --sim");
    }
    gt_out_path = args.Get("gt-out");
    if (args.Has("sim-seed")) {
      if (sim_path.empty()) return UsageError("--sim-seed needs --sim");
      sim_seed = args.GetInt("sim-seed", 0);
      if (*sim_seed < 0) return UsageError("--sim-seed must be >= 0");
    }
    trajectory_path = args.Require("trajectory");
    report_dir = args.Get("report");
    map_path = args.Get("map");
    map_config_path = args.Get("map-config", std::string(ICGM_CONFIG_DIR) + "/map.yaml");
    pose_graph = args.Has("pose-graph");
    if (pose_graph && map_path.empty()) return UsageError("--pose-graph needs --map");
    refine = args.Has("refine");
    if (refine && map_path.empty()) return UsageError("--refine needs --map");
    config_path = args.Get("config", std::string(ICGM_CONFIG_DIR) + "/odometry.yaml");
    icgm_config_path = args.Get("icgm-config", std::string(ICGM_CONFIG_DIR) + "/icgm.yaml");
    camera_path = args.Get("camera", std::string(ICGM_CONFIG_DIR) + "/camera/tum_fr1.yaml");
    camera_given = args.Has("camera");
    max_frames = args.GetInt("max-frames", -1);
    threads = args.GetInt("threads", 1);
    no_icgm = args.Has("no-icgm");
    no_wheel_gate = args.Has("no-wheel-gate");
    if (args.Has("max-frames") && max_frames < 1) return UsageError("--max-frames must be >= 1");
    if (threads < 1 || threads > 64) return UsageError("--threads must be in [1, 64]");
    extrinsic_from_config = args.Has("extrinsic-from-config");
    camera_only = args.Has("camera-only");
    if (extrinsic_from_config && camera_only) {
      return UsageError("give at most one of --extrinsic-from-config, --camera-only");
    }
    if ((extrinsic_from_config || camera_only) && bag_path.empty()) {
      return UsageError("--extrinsic-from-config and --camera-only apply to --bag");
    }
  } catch (const std::invalid_argument& e) {
    return UsageError(e.what());
  }
  cv::setNumThreads(threads);

  icgm::FrontendOptions options;
  SourceInfo info;
  NextFrame next;
  try {
    const auto config = icgm::OptionReader::FromFile(config_path);
    const bool icgm_given = std::filesystem::exists(icgm_config_path) ||
                            icgm_config_path != std::string(ICGM_CONFIG_DIR) + "/icgm.yaml";
    const auto icgm_config = icgm_given ? icgm::OptionReader::FromFile(icgm_config_path)
                                        : icgm::OptionReader::FromString("{}");
    icgm::ReadFrontendOptions(config, icgm_config, &options);
    if (no_icgm) options.use_icgm = false;
    if (no_wheel_gate) {
      options.fusion.max_vision_wheel_disagreement_m = 0.0;
      options.fusion.max_vision_wheel_disagreement_deg = 0.0;
    }
    const icgm::CameraIntrinsics camera = icgm::LoadCameraIntrinsics(camera_path);
    if (!tum_dir.empty()) {
      next = OpenTum(tum_dir, camera, &info);
    } else if (!bag_path.empty()) {
      next = OpenBag(bag_path, camera_given ? std::optional(camera) : std::nullopt, &info);
      // camera_info has no timing or depth calibration: an explicit --camera file supplies the
      // depth time offset, the depth correction and the rolling shutter.
      if (camera_given) icgm::CopySensorCalibration(camera, &info.intrinsics);
    } else {
      next = OpenSim(sim_path, sim_seed, &info);
    }
    if (!bag_path.empty() && !info.base_to_camera && !info.wheel_odometry.empty()) {
      // Wheel motion reaches the camera through the extrinsic: never assume one silently.
      if (camera_only) {
        info.wheel_odometry.clear();
      } else if (!extrinsic_from_config) {
        throw icgm::LoadError(
            "bag '" + bag_path + "' has wheel odometry but no base_link -> camera transform on "
            "/tf_static; give --extrinsic-from-config (fusion.base_to_camera_* of " + config_path +
            ") or --camera-only (ignore the wheels)");
      }
    } else if (info.base_to_camera) {
      options.fusion.base_to_camera = *info.base_to_camera;
    }
    if (!map_path.empty()) {
      // Checked before processing: a long run must not end without its map.
      const icgm::Status writable = icgm::CheckMapWritable(map_path);
      if (!writable.ok()) throw icgm::LoadError(writable.reason());
    }
  } catch (const icgm::LoadError& e) {
    std::fprintf(stderr, "icgm_slam_offline: %s\n", e.what());
    return 1;
  } catch (const std::invalid_argument& e) {
    return UsageError(e.what());
  }

  // With --map the hybrid map runs behind the front end (loop closure, eq. 6.2 / 6.4) and the
  // trajectory is the corrected map trajectory; without it, the front end alone.
  std::unique_ptr<icgm::SlamSystem> slam;
  std::unique_ptr<icgm::RgbdFrontend> own_frontend;
  if (!map_path.empty()) {
    icgm::SlamOptions slam_options;
    slam_options.frontend = options;
    try {
      const auto map_config = icgm::OptionReader::FromFile(map_config_path);
      icgm::ReadMapSlamOptions(map_config, &slam_options);
      if (pose_graph) slam_options.map.loop_closure.correction = "pose_graph";
    } catch (const icgm::LoadError& e) {
      std::fprintf(stderr, "icgm_slam_offline: %s\n", e.what());
      return 1;
    }
    slam = std::make_unique<icgm::SlamSystem>(slam_options, info.intrinsics);
  } else {
    own_frontend = std::make_unique<icgm::RgbdFrontend>(options, info.intrinsics);
  }
  const icgm::RgbdFrontend& frontend = slam ? slam->frontend() : *own_frontend;
  const size_t total = max_frames > 0
                           ? std::min<size_t>(info.expected_frames, static_cast<size_t>(max_frames))
                           : info.expected_frames;
  icgm::ProgressBar progress(total, options.use_icgm ? "odometry (ICGM)" : "odometry (no ICGM)");
  icgm::Trajectory trajectory;
  std::vector<double> t_feat, t_match, t_icgm, t_reg, t_fusion, t_front, t_total, t_cpu;
  // Reprojection rms of the accepted registrations: a residual without ground truth (camera
  // timing and calibration show in it).
  std::vector<double> reprojection_rms_px;
  std::map<std::string, size_t> failures;
  std::ofstream frames_csv;
  if (!report_dir.empty()) {
    std::error_code ec;
    std::filesystem::create_directories(report_dir, ec);
    frames_csv.open(report_dir + "/frames.csv");
    if (!frames_csv) {
      std::fprintf(stderr, "icgm_slam_offline: cannot write %s/frames.csv\n", report_dir.c_str());
      return 1;
    }
    frames_csv << "stamp,source,features,matches,kept,matches_3d,inliers,inlier_ratio,rmse_m,"
                  "keyframe,features_ms,matching_ms,icgm_ms,registration_ms,total_ms,"
                  "dynamic_matches,dynamic_inliers,status\n";
  }
  // Matches given to registration (and inliers of accepted registrations) on pedestrians.
  icgm::tools::DynamicMatchCount dynamic_total;
  size_t masked_frames = 0, frames_with_dynamic_inliers = 0;
  // Accepted registrations whose inliers are mostly on pedestrians: the pose followed a walker.
  size_t frames_dynamic_majority = 0;
  size_t wheel_next = 0;
  OfflineFrame frame;
  std::string error;
  while ((max_frames < 0 || trajectory.size() < static_cast<size_t>(max_frames)) &&
         next(&frame, &error)) {
    // Wheel odometry received up to (slightly after) the frame, as a live system would have.
    while (wheel_next < info.wheel_odometry.size() &&
           icgm::DurationSeconds(info.wheel_odometry[wheel_next].stamp, frame.stamp) <= 0.05) {
      const auto& w = info.wheel_odometry[wheel_next];
      if (slam) {
        slam->AddWheelOdometry(w.stamp, w.pose);
      } else {
        own_frontend->AddWheelOdometry(w.stamp, w.pose);
      }
      ++wheel_next;
    }
    const double cpu0 = ThreadCpuMs();
    const icgm::FrontendFrameResult r =
        slam ? slam->ProcessFrame(frame.stamp, frame.bgr, frame.depth_m, frame.depth_stamp).frontend
             : own_frontend->ProcessFrame(frame.stamp, frame.bgr, frame.depth_m,
                                          frame.depth_stamp);
    const double cpu_ms = ThreadCpuMs() - cpu0;
    if (!r.status.ok()) {
      ++failures["input: " + r.status.reason().substr(0, 40)];
      // A frame out of time order is ignored by the front end; others got a fallback pose.
      if (!trajectory.empty() && r.stamp <= trajectory.back().stamp) continue;
    }
    trajectory.push_back({r.stamp, r.odom_camera});
    const icgm::StageTimes& t = r.times;
    icgm::tools::DynamicMatchCount dynamic;
    if (!frame.dynamic_mask.empty() && r.frame_index > 0) {
      static const std::vector<int> kNone;
      dynamic = icgm::tools::CountDynamicMatches(
          frame.dynamic_mask, r.registered_px,
          r.registration.status.ok() ? r.registration.inlier_indices : kNone);
      dynamic_total += dynamic;
      ++masked_frames;
      frames_with_dynamic_inliers += dynamic.dynamic_inliers > 0;
      frames_dynamic_majority += 2 * dynamic.dynamic_inliers > dynamic.inliers;
    }
    if (r.frame_index > 0) {
      t_feat.push_back(t.undistort_ms + t.features_ms);
      t_match.push_back(t.matching_ms);
      t_icgm.push_back(t.icgm_ms);
      t_reg.push_back(t.registration_ms);
      t_fusion.push_back(t.fusion_ms);
      t_front.push_back(t.undistort_ms + t.features_ms + t.matching_ms + t.icgm_ms +
                        t.registration_ms);
      t_total.push_back(t.total_ms);
      t_cpu.push_back(cpu_ms);
      if (r.registration.status.ok() && r.registration.reprojection_rms_px > 0.0) {
        reprojection_rms_px.push_back(r.registration.reprojection_rms_px);
      }
      if (!r.registration.status.ok()) {
        const std::string& why = r.registration.status.reason();
        ++failures[why.substr(0, why.find(':'))];
      }
    }
    if (frames_csv.is_open()) {
      const auto& g = r.registration;
      frames_csv << r.stamp.ToString() << ',' << icgm::MotionSourceName(r.source) << ','
                 << r.num_features << ',' << r.num_matches << ',' << r.num_icgm_kept << ','
                 << g.matches_3d << ',' << g.inliers << ',' << g.inlier_ratio << ',' << g.rmse_m
                 << ',' << r.new_keyframe << ',' << t.features_ms << ',' << t.matching_ms << ','
                 << t.icgm_ms << ',' << t.registration_ms << ',' << t.total_ms << ','
                 << dynamic.dynamic_matches << ',' << dynamic.dynamic_inliers << ",\""
                 << (g.status.ok() ? "ok" : g.status.reason()) << "\"\n";
    }
    progress.Update(trajectory.size());
  }
  progress.Finish();
  const size_t skipped_frames = *info.skipped_frames;
  if (!error.empty())
    std::fprintf(stderr, "icgm_slam_offline: input ended early: %s\n", error.c_str());
  if (trajectory.empty()) {
    std::fprintf(stderr, "icgm_slam_offline: no frames processed\n");
    return 1;
  }
  // The front end's own trajectory, kept for its ATE beside the map's.
  icgm::Trajectory frontend_trajectory;
  if (slam) {
    frontend_trajectory = trajectory;
    // Saved first: whatever happens next, the map built so far is kept (atomic save).
    trajectory = slam->MapTrajectory();
    const icgm::Status saved = slam->Save(map_path);
    if (!saved.ok()) {
      std::fprintf(stderr, "icgm_slam_offline: map not saved: %s\n", saved.reason().c_str());
      return 1;
    }
    std::printf("map: %d keyframes, %zu loop closures, saved to %s\n", slam->map().size(),
                slam->loop_closures().size(), map_path.c_str());
    if (refine || slam->options().map_refinement.enabled) {
      icgm::MapRefinementSummary rs;
      const icgm::Status refined = slam->RefineMap(&rs);
      if (!refined.ok()) {
        std::fprintf(stderr, "icgm_slam_offline: map not refined (kept as saved): %s\n",
                     refined.reason().c_str());
      } else {
        trajectory = slam->MapTrajectory();
        const icgm::Status resaved = slam->Save(map_path);
        if (!resaved.ok()) {
          std::fprintf(stderr, "icgm_slam_offline: refined map not saved: %s\n",
                       resaved.reason().c_str());
          return 1;
        }
        const icgm::BaSummary& ba = rs.bundle_adjustment;
        std::printf(
            "map refined: %d of %d keyframe pairs registered, %d points, %d observations "
            "(%d outliers), residual %.2f -> %.2f sigma, %.2f s; saved again\n",
            rs.pairs_used, rs.pairs_tried, ba.points, ba.observations, ba.outliers,
            ba.initial_rms, ba.final_rms, rs.time_s);
      }
    }
  }
  try {
    icgm::WriteTumTrajectory(trajectory_path, trajectory);
    if (!gt_out_path.empty()) {
      if (info.groundtruth.empty()) {
        std::fprintf(stderr, "icgm_slam_offline: --gt-out: the input has no ground truth\n");
      } else {
        icgm::WriteTumTrajectory(gt_out_path, info.groundtruth);
      }
    }
  } catch (const icgm::LoadError& e) {
    std::fprintf(stderr, "icgm_slam_offline: %s\n", e.what());
    return 1;
  }

  std::string summary;
  char line[256];
  auto add = [&](const char* fmt, auto... v) {
    std::snprintf(line, sizeof(line), fmt, v...);
    summary += line;
  };
  add("frames %zu, keyframes %zu, ICGM %s, threads %d\n", trajectory.size(),
      frontend.num_keyframes(), options.use_icgm ? "on" : "off", threads);
  if (skipped_frames > 0) {
    add("skipped %zu unreadable frames (see the warnings above)\n", skipped_frames);
  }
  add("%-22s %8s %8s %8s   (wall time unless noted)\n", "stage [ms]", "mean", "median", "p95");
  const std::pair<const char*, const std::vector<double>*> stages[] = {
      {"features", &t_feat},
      {"matching", &t_match},
      {"icgm", &t_icgm},
      {"registration", &t_reg},
      {"fusion", &t_fusion},
      {"front end (4 stages)", &t_front},
      {"total per frame", &t_total},
      {"total, thread CPU", &t_cpu}};
  for (const auto& [name, v] : stages) {
    const Summary s = Summarize(*v);
    add("%-22s %8.2f %8.2f %8.2f\n", name, s.mean, s.median, s.p95);
  }
  const icgm::FusionStats& fs = frontend.fusion_stats();
  add("motion from vision: %.1f%% of frames, %.1f%% of distance (%.3f m)\n",
      100.0 * fs.VisionShareByFrames(), 100.0 * fs.VisionShareByDistance(), fs.total_distance_m());
  for (size_t k = 0; k < icgm::kNumMotionSources; ++k) {
    add("  %-18s %6zu frames %8.3f m\n", icgm::MotionSourceName(static_cast<icgm::MotionSource>(k)),
        fs.frames[k], fs.distance_m[k]);
  }
  if (!reprojection_rms_px.empty()) {
    const Summary s = Summarize(reprojection_rms_px);
    add("registration reprojection rms [px]: mean %.3f, median %.3f, p95 %.3f (%zu frames)\n",
        s.mean, s.median, s.p95, reprojection_rms_px.size());
  }
  for (const auto& [why, n] : failures) add("  registration failed %4zu x: %s\n", n, why.c_str());
  if (masked_frames > 0) {
    const icgm::tools::DynamicMatchCount& d = dynamic_total;
    add("matches on pedestrians: %.2f%% of registration matches (%zu / %zu), %.2f%% of inliers "
        "(%zu / %zu)\n",
        100.0 * d.MatchShare(), d.dynamic_matches, d.matches, 100.0 * d.InlierShare(),
        d.dynamic_inliers, d.inliers);
    add("  frames with pedestrian inliers %zu of %zu, with mostly pedestrian inliers %zu\n",
        frames_with_dynamic_inliers, masked_frames, frames_dynamic_majority);
  }
  if (!info.groundtruth.empty()) {
    icgm::TrajectoryEvaluation ev;
    const icgm::Status s =
        icgm::EvaluateTrajectory(info.groundtruth, trajectory, icgm::TrajectoryEvalOptions(), &ev);
    if (s.ok() && !report_dir.empty()) {
      std::ofstream ate(report_dir + "/ate.csv");
      ate << "stamp,ate_m\n";
      for (size_t i = 0; i < ev.stamps.size(); ++i) {
        ate << ev.stamps[i].ToString() << ',' << ev.ate_m[i] << '\n';
      }
    }
    if (s.ok()) {
      icgm::TrajectoryEvaluation fev;
      if (!frontend_trajectory.empty() &&
          icgm::EvaluateTrajectory(info.groundtruth, frontend_trajectory,
                                   icgm::TrajectoryEvalOptions(), &fev)
              .ok()) {
        add("front end ATE rmse %.4f m (before the map's loop correction)\n", fev.ate.rmse);
      }
      add("ATE rmse %.4f m, mean %.4f m, max %.4f m (%zu poses); RPE %.4f m/s, %.3f deg/s\n",
          ev.ate.rmse, ev.ate.mean, ev.ate.max, ev.ate.count, ev.rpe_translation_m_per_s.rmse,
          ev.rpe_rotation_deg_per_s.rmse);
    } else {
      add("ATE not available: %s\n", s.reason().c_str());
      icgm::Trajectory gt = info.groundtruth;
      icgm::SortByStamp(&gt);
      icgm::tools::FirstPoseAte fp;
      if (icgm::tools::EvaluateFirstPoseAte(gt, trajectory, 0.1, &fp).ok()) {
        add("ATE aligned at the first pose (upper bound): rmse %.4f m, max %.4f m (%zu poses)\n",
            fp.rmse_m, fp.max_m, fp.count);
      }
    }
  }
  add("trajectory written to %s\n", trajectory_path.c_str());
  std::printf("%s", summary.c_str());
  if (!report_dir.empty()) {
    std::ofstream out(report_dir + "/summary.txt");
    out << summary;
  }
  return 0;
}
