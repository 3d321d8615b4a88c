// icgm_slam_offline: runs the SLAM system of the nodelets (core/slam/slam_system.h: features ->
// matching -> ICGM -> registration -> fusion, and with --map the hybrid map) through the core
// driver RunSlam over a TUM RGB-D folder, a rosbag or a simulator scenario rendered in process,
// without a ROS master, as fast as it can, and writes the camera trajectory in TUM format.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <functional>
#include <limits>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>

#include "core/common/option_reader.h"
#include "core/common/progress_bar.h"
#include "core/common/sample_summary.h"
#include "core/dataset/camera_options.h"
#include "core/dataset/trajectory.h"
#include "core/eval/trajectory_evaluation.h"
#include "core/map/map_options.h"
#include "core/map/map_store.h"
#include "core/odometry/hypothesis_evidence.h"
#include "core/slam/slam_runner.h"
#include "core/slam/slam_system.h"
#include "tools/cli_args.h"
#include "tools/dynamic_match_stats.h"
#include "tools/first_pose_ate.h"
#include "tools/offline_sources.h"

namespace {

constexpr char kUsage[] =
    "usage: icgm_slam_offline (--tum DIR | --bag FILE | --sim SCENARIO.yaml)\n"
    "                         --trajectory OUT.txt [--gt-out GT.txt] [--sim-seed N]\n"
    "                         [--config odometry.yaml] [--icgm-config icgm.yaml]\n"
    "                         [--camera camera.yaml] [--report DIR] [--no-icgm]\n"
    "                         [--no-wheel-gate] [--extrinsic-from-config | --camera-only]\n"
    "                         [--oracle-static]\n"
    "                         [--max-frames N] [--threads 1]\n"
    "                         [--map OUT.db [--map-config map.yaml] [--pose-graph]\n"
    "                          [--refine] [--merge-into EXISTING.db | --localization LEARNED.db]\n"
    "                          [--no-loop-closure]] [--profile default|thesis]\n"
    "  Runs the RGB-D visual odometry front end offline and writes the camera trajectory\n"
    "  (TUM format). Prints per-stage timing and the share of motion from vision; with\n"
    "  ground truth, also the ATE; with ground-truth dynamic masks (simulator, simulated\n"
    "  bags), the share of registration matches on pedestrians. --sim renders the scenario\n"
    "  in process (camera, wheel odometry and extrinsic from the simulator; --camera is\n"
    "  ignored); --sim-seed replaces the scenario's seed (same scene layout rules, another\n"
    "  world, crowd and odometry noise). --gt-out writes the ground-truth camera trajectory\n"
    "  (TUM format).\n"
    "  --report DIR writes frames.csv, summary.txt and matches.csv (every match given to\n"
    "  registration: frame and reference indices, both pixels, current depth, inlier flag and,\n"
    "  with ground-truth masks, the distance to the walkers' silhouettes in both frames).\n"
    "  With frontend.select_by_evidence, frames.csv also names the hypothesis that won the\n"
    "  evidence choice (kind, score, depth and edge counts, its inliers on walkers) and\n"
    "  hypotheses.csv lists every judged hypothesis per frame with the predicted motion.\n"
    "  trend_votes.csv lists the reference keypoints frontend.residual_trend_* voted out, with\n"
    "  their distance to the walkers' silhouettes in the reference (ground-truth masks).\n"
    "  --map builds the hybrid map behind the front end (loop closure, eq. 6.2/6.4), writes the\n"
    "  corrected map trajectory and saves the map (SQLite, atomic) to OUT.db; --pose-graph\n"
    "  corrects loops with the Ceres pose-graph back end instead of the thesis's eq. 6.4\n"
    "  semi-consensus. --refine (or map_refinement: enabled in the map config) bundle-adjusts\n"
    "  the whole map at the end and saves it again.\n"
    "  --merge-into adds the run as a new session to EXISTING.db (the result goes to --map).\n"
    "  --localization locates the run in LEARNED.db without changing it (localization mode,\n"
    "  alpha = 1; the trajectory is in the learned map's frame; keyframes go where the map\n"
    "  config's localization.keyframes says, saved only to --map, which must be another file).\n"
    "  --no-loop-closure chains keyframes without loop-closure queries.\n"
    "  --oracle-static (diagnosis, needs ground-truth masks: simulator, simulated bags) blanks\n"
    "  the depth under the walkers' mask before the system sees a frame, so only static points\n"
    "  can register: an upper bound for what removing walkers can give.\n"
    "  --profile thesis reads odometry.yaml, icgm.yaml and map.yaml from config/thesis (the\n"
    "  thesis's method as written; README: thesis vs default) instead of config/; --config,\n"
    "  --icgm-config and --map-config still replace single files.\n"
    "  --no-wheel-gate turns off the vision/wheel consistency gate of the fusion (the thesis's\n"
    "  fusion: vision whenever registration succeeds). With --bag the intrinsics come from\n"
    "  camera_info (a bag without it needs --camera), but an explicit --camera also\n"
    "  sets the depth time offset and correction and the rolling shutter (depth_time_offset_s,\n"
    "  depth_correction, readout_s, first_row_offset_s), which camera_info cannot carry.\n"
    "  A bag with wheel odometry needs the base_link -> camera extrinsic on /tf_static, or\n"
    "  --extrinsic-from-config (fusion.base_to_camera_* of --config), or --camera-only (the\n"
    "  wheels are ignored). A TUM image that cannot be read is skipped with a warning and\n"
    "  counted. --map is checked before processing: a read-only map file is never replaced.\n"
    "  Input that ends early (a corrupt bag) exits 1 after writing what was built.\n";
constexpr icgm::tools::ToolInfo kTool{"icgm_slam_offline", kUsage};

int UsageError(const std::string& message) { return icgm::tools::UsageError(kTool, message); }

using icgm::Summarize;
using Summary = icgm::SampleSummary;

// What the tool reports per frame beyond the driver's own report.
struct FrameBook {
  icgm::Trajectory trajectory;  // the front end's odometry, one pose per frame in time order
  std::vector<double> front_end_ms;
  // Reprojection rms of the accepted registrations: a residual without ground truth (camera
  // timing and calibration show in it).
  std::vector<double> reprojection_rms_px;
  std::map<std::string, size_t> failures;
  // Localization: why keyframes were not located in the learned map.
  std::map<std::string, size_t> unlocated;
  // Matches given to registration (and inliers of accepted registrations) on pedestrians.
  icgm::tools::DynamicMatchCount dynamic_total;
  size_t masked_frames = 0, frames_with_dynamic_inliers = 0;
  // Accepted registrations whose inliers are mostly on pedestrians: the pose followed a walker.
  size_t frames_dynamic_majority = 0;
  size_t prior_gated = 0;  // registrations that gave way to the prediction (prior gate)
  // Frames whose registered step / prediction the velocity gate set aside / dropped;
  // frames whose motion prior was reset (prior_reset).
  size_t velocity_gate_rejected = 0, velocity_gate_dropped_prior = 0, prior_reset = 0;
  size_t registrations_agreed = 0, keyframes_postponed = 0;  // registration agreement
  std::vector<double> registration_spreads_m;  // frames registered more than once
  size_t new_keyframes = 0, velocity_rebased = 0;  // keyframes; those that rebased the velocity
  size_t prior_released = 0;                       // frames whose motion prior was released
  size_t anchor_linked = 0;  // frames whose pose an anchor keyframe's registration corrected
  std::ofstream frames_csv;
  // Every hypothesis of the evidence choice per frame (report dir, hypotheses.csv).
  std::ofstream hypotheses_csv;
  // Every match given to registration (report dir, matches.csv): both pixels, the current
  // depth, inlier or not and, with ground-truth masks, its distance to the walkers' silhouettes
  // in both frames (-1 without masks).
  std::ofstream matches_csv;
  std::map<size_t, cv::Mat> mask_distance_px;  // per frame index: distance to the mask, <= 255
  // residual_trend: reference keypoints voted out, and those on walkers by the reference's
  // ground-truth mask (frames of the last few seconds kept).
  // Only with the trend on are the masks kept (votes name earlier reference frames).
  bool trend_on = false;
  size_t trend_voted = 0, trend_voted_checked = 0, trend_voted_on_walkers = 0;
  std::map<size_t, cv::Mat> recent_masks;

  void AddTrendVotes(const icgm::SlamInputFrame& input, const icgm::FrontendFrameResult& r) {
    if (!trend_on) return;  // then no frame has votes
    if (!input.dynamic_mask.empty()) {
      recent_masks[r.frame_index] = input.dynamic_mask.clone();
      while (recent_masks.size() > 128) recent_masks.erase(recent_masks.begin());
    }
    trend_voted += r.trend_voted_reference_px.size();
    if (!r.reference_index || r.trend_voted_reference_px.empty()) return;
    const auto it = recent_masks.find(*r.reference_index);
    if (it == recent_masks.end()) return;
    trend_voted_checked += r.trend_voted_reference_px.size();
    trend_voted_on_walkers +=
        icgm::tools::CountDynamicMatches(it->second, r.trend_voted_reference_px, {})
            .dynamic_matches;
    if (!trend_csv.is_open()) return;
    cv::Mat outside = it->second == 0, distance;
    cv::distanceTransform(outside, distance, cv::DIST_L2, 3);
    for (const cv::Point2f& p : r.trend_voted_reference_px) {
      const int x = std::clamp(cvRound(p.x), 0, distance.cols - 1);
      const int y = std::clamp(cvRound(p.y), 0, distance.rows - 1);
      trend_csv << r.frame_index << ',' << *r.reference_index << ',' << p.x << ',' << p.y << ','
                << distance.at<float>(y, x) << '\n';
    }
  }
  // residual_trend: each voted-out reference keypoint with its distance to the walkers' mask in
  // the reference (report dir, trend_votes.csv; 0: on a walker).
  std::ofstream trend_csv;

  void AddMatches(const icgm::SlamInputFrame& input, const icgm::FrontendFrameResult& r) {
    if (!matches_csv.is_open()) return;
    cv::Mat distance8;  // empty without ground-truth masks: distances are written as -1
    if (!input.dynamic_mask.empty()) {
      cv::Mat outside = input.dynamic_mask == 0, distance;
      cv::distanceTransform(outside, distance, cv::DIST_L2, 3);
      distance.convertTo(distance8, CV_8U);
      mask_distance_px[r.frame_index] = distance8;
      while (mask_distance_px.size() > 64) mask_distance_px.erase(mask_distance_px.begin());
    }
    if (!r.reference_index || r.registered_reference_px.size() != r.registered_px.size()) return;
    const auto ref_it = mask_distance_px.find(*r.reference_index);
    std::vector<uint8_t> inlier(r.registered_px.size(), 0);
    if (r.registration.status.ok()) {
      for (const int k : r.registration.inlier_indices) inlier[k] = 1;
    }
    const auto at = [](const cv::Mat& m, const cv::Point2f& p) -> int {
      const int x = cvRound(p.x), y = cvRound(p.y);
      if (m.empty() || x < 0 || y < 0 || x >= m.cols || y >= m.rows) return -1;
      return m.at<uint8_t>(y, x);
    };
    for (size_t k = 0; k < r.registered_px.size(); ++k) {
      const cv::Point2f& c = r.registered_px[k];
      const cv::Point2f& f = r.registered_reference_px[k];
      const int x = cvRound(c.x), y = cvRound(c.y);
      const float depth = (x >= 0 && y >= 0 && x < input.depth_m.cols && y < input.depth_m.rows)
                              ? input.depth_m.at<float>(y, x)
                              : std::nanf("");
      matches_csv << r.frame_index << ',' << *r.reference_index << ',' << f.x << ',' << f.y << ','
                  << c.x << ',' << c.y << ',' << depth << ',' << int(inlier[k]) << ','
                  << at(distance8, c) << ','
                  << (ref_it == mask_distance_px.end() ? -1 : at(ref_it->second, f)) << '\n';
    }
  }

  void Add(const icgm::SlamInputFrame& input, const icgm::FrontendFrameResult& r) {
    if (!r.status.ok()) {
      ++failures["input: " + r.status.reason().substr(0, 40)];
      // A frame out of time order is ignored by the front end; others got a fallback pose.
      if (!trajectory.empty() && r.stamp <= trajectory.back().stamp) return;
    }
    trajectory.push_back({r.stamp, r.odom_camera});
    const icgm::StageTimes& t = r.times;
    icgm::tools::DynamicMatchCount dynamic;
    if (!input.dynamic_mask.empty() && r.frame_index > 0) {
      static const std::vector<int> kNone;
      dynamic = icgm::tools::CountDynamicMatches(
          input.dynamic_mask, r.registered_px,
          r.registration.status.ok() ? r.registration.inlier_indices : kNone);
      dynamic_total += dynamic;
      ++masked_frames;
      frames_with_dynamic_inliers += dynamic.dynamic_inliers > 0;
      frames_dynamic_majority += 2 * dynamic.dynamic_inliers > dynamic.inliers;
    }
    AddMatches(input, r);
    AddTrendVotes(input, r);
    // The evidence choice's hypotheses, with their inliers on walkers (-1 without masks), and
    // the predicted motion as one more row (kind "predicted", never chosen).
    std::vector<long> hypothesis_dynamic(r.hypotheses.size(), -1);
    const auto write_pose = [this](const icgm::Pose3& p) {
      // T_reference_current: translation (m) and rotation vector (rad).
      const Eigen::AngleAxisd rotation(p.rotation());
      const Eigen::Vector3d t = p.translation(), w = rotation.angle() * rotation.axis();
      hypotheses_csv << ',' << t.x() << ',' << t.y() << ',' << t.z() << ',' << w.x() << ','
                     << w.y() << ',' << w.z() << '\n';
    };
    if (hypotheses_csv.is_open() && !r.hypotheses.empty() && r.predicted_reference_current) {
      hypotheses_csv << r.frame_index << ','
                     << (r.reference_index ? static_cast<long>(*r.reference_index) : -1L)
                     << ",-1,predicted,0,0,-1,0,0,nan,0,nan";
      write_pose(*r.predicted_reference_current);
    }
    for (size_t i = 0; i < r.hypotheses.size(); ++i) {
      const icgm::JudgedHypothesis& h = r.hypotheses[i];
      if (!input.dynamic_mask.empty()) {
        std::vector<int> all(h.inlier_px.size());
        for (size_t k = 0; k < all.size(); ++k) all[k] = static_cast<int>(k);
        hypothesis_dynamic[i] = static_cast<long>(
            icgm::tools::CountDynamicMatches(input.dynamic_mask, h.inlier_px, all)
                .dynamic_inliers);
      }
      if (hypotheses_csv.is_open()) {
        hypotheses_csv << r.frame_index << ','
                       << (r.reference_index ? static_cast<long>(*r.reference_index) : -1L) << ','
                       << i << ',' << icgm::HypothesisKindName(h.kind) << ','
                       << (static_cast<int>(i) == r.chosen_hypothesis) << ',' << h.inliers << ','
                       << hypothesis_dynamic[i] << ',' << h.evidence.depth_agreeing << ','
                       << h.evidence.edges_agreeing << ',' << h.score << ','
                       << h.prediction_distance << ',' << h.median_depth_m;
        write_pose(h.relative_pose);
      }
    }
    prior_gated += r.prior_gated;
    velocity_gate_rejected += r.velocity_gate_rejected;
    velocity_gate_dropped_prior += r.velocity_gate_dropped_prior;
    prior_reset += r.prior_reset;
    registrations_agreed += r.registrations_agreed;
    if (std::isfinite(r.registration_spread_m)) {
      registration_spreads_m.push_back(r.registration_spread_m);
    }
    keyframes_postponed += r.keyframe_postponed;
    new_keyframes += r.new_keyframe;
    velocity_rebased += r.velocity_rebased;
    prior_released += r.motion_prior_released;
    anchor_linked += r.anchor_linked;
    if (r.frame_index > 0) {
      front_end_ms.push_back(t.undistort_ms + t.features_ms + t.matching_ms + t.icgm_ms +
                             t.registration_ms);
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
                 << dynamic.dynamic_matches << ',' << dynamic.dynamic_inliers << ',';
      // The evidence choice: how many hypotheses, the winner's kind, score terms and inliers
      // (on walkers: -1 without masks), the best score among the others.
      const int c = r.chosen_hypothesis;
      if (c >= 0 && static_cast<size_t>(c) < r.hypotheses.size()) {
        const icgm::JudgedHypothesis& h = r.hypotheses[c];
        double runner_up = std::nan("");
        for (size_t i = 0; i < r.hypotheses.size(); ++i) {
          if (static_cast<int>(i) != c && !(r.hypotheses[i].score <= runner_up)) {
            runner_up = r.hypotheses[i].score;
          }
        }
        frames_csv << r.hypotheses.size() << ',' << icgm::HypothesisKindName(h.kind) << ','
                   << h.score << ',' << h.evidence.depth_agreeing << ','
                   << h.evidence.edges_agreeing << ',' << h.inliers << ','
                   << hypothesis_dynamic[c] << ',' << runner_up << ',';
      } else {
        frames_csv << "0,none,nan,0,0,0,-1,nan,";
      }
      frames_csv << '"' << (g.status.ok() ? "ok" : g.status.reason()) << "\"\n";
    }
  }
};

}  // namespace

int main(int argc, char** argv) {
  std::string map_path, map_config_path, merge_path, learned_path;
  bool pose_graph = false, refine = false, no_loop_closure = false;
  bool camera_given = false;  // --camera given (else only the fallback for a bag)
  std::string tum_dir, bag_path, sim_path, gt_out_path, trajectory_path, report_dir, config_path,
      icgm_config_path, camera_path;
  int max_frames = -1, threads = 1;
  std::optional<int> sim_seed;
  bool no_icgm = false;
  bool oracle_static = false;
  bool no_wheel_gate = false;
  bool extrinsic_from_config = false, camera_only = false;
  try {
    const icgm::tools::CliArgs args(
        argc, argv,
        {"tum", "bag", "sim", "sim-seed", "gt-out", "config", "icgm-config", "camera",
         "trajectory", "report", "max-frames", "threads", "map", "map-config", "merge-into",
         "localization", "profile"},
        {"no-icgm", "no-wheel-gate", "pose-graph", "refine", "extrinsic-from-config",
         "camera-only", "no-loop-closure", "oracle-static"});
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
    const std::string profile = args.Get("profile", "default");
    if (profile != "default" && profile != "thesis") {
      return UsageError("--profile must be default or thesis, not '" + profile + "'");
    }
    const std::string profile_dir =
        std::string(ICGM_CONFIG_DIR) + (profile == "thesis" ? "/thesis" : "");
    map_config_path = args.Get("map-config", profile_dir + "/map.yaml");
    merge_path = args.Get("merge-into");
    learned_path = args.Get("localization");
    pose_graph = args.Has("pose-graph");
    refine = args.Has("refine");
    no_loop_closure = args.Has("no-loop-closure");
    oracle_static = args.Has("oracle-static");
    for (const char* needs_map :
         {"pose-graph", "refine", "merge-into", "localization", "no-loop-closure"}) {
      if (args.Has(needs_map) && map_path.empty()) {
        return UsageError(std::string("--") + needs_map + " needs --map");
      }
    }
    if (!merge_path.empty() && !learned_path.empty()) {
      return UsageError("give at most one of --merge-into, --localization");
    }
    if (!learned_path.empty() && std::filesystem::exists(map_path) &&
        std::filesystem::exists(learned_path) &&
        std::filesystem::equivalent(map_path, learned_path)) {
      return UsageError("--localization never writes the learned map: give --map another file");
    }
    config_path = args.Get("config", profile_dir + "/odometry.yaml");
    icgm_config_path = args.Get("icgm-config", profile_dir + "/icgm.yaml");
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

  icgm::SlamOptions slam_options;
  icgm::FrontendOptions& options = slam_options.frontend;
  icgm::tools::OfflineSource source;
  std::unique_ptr<icgm::SlamSystem> slam;
  try {
    const auto config = icgm::OptionReader::FromFile(config_path);
    const bool icgm_given = std::filesystem::exists(icgm_config_path) ||
                            icgm_config_path != std::string(ICGM_CONFIG_DIR) + "/icgm.yaml";
    const auto icgm_config = icgm_given ? icgm::OptionReader::FromFile(icgm_config_path)
                                        : icgm::OptionReader::FromString("{}");
    icgm::ReadFrontendOptions(config, icgm_config, &options);
    icgm::ReadOptions(icgm_config, &slam_options.map_features.tracker);
    if (no_icgm) options.use_icgm = false;
    if (no_wheel_gate) {
      options.fusion.max_vision_wheel_disagreement_m = 0.0;
      options.fusion.max_vision_wheel_disagreement_deg = 0.0;
    }
    const icgm::CameraIntrinsics camera = icgm::LoadCameraIntrinsics(camera_path);
    if (!tum_dir.empty()) {
      source = icgm::tools::OpenTumSource(tum_dir, camera, kTool.name);
    } else if (!bag_path.empty()) {
      source = icgm::tools::OpenBagSource(bag_path,
                                          camera_given ? std::optional(camera) : std::nullopt);
      // camera_info has no timing or depth calibration: an explicit --camera file supplies the
      // depth time offset, the depth correction and the rolling shutter.
      if (camera_given) icgm::CopySensorCalibration(camera, &source.intrinsics);
    } else {
      source = icgm::tools::OpenSimSource(sim_path, sim_seed);
    }
    if (!bag_path.empty() && !source.base_to_camera && !source.wheel_odometry.empty()) {
      // Wheel motion reaches the camera through the extrinsic: never assume one silently.
      if (camera_only) {
        source.wheel_odometry.clear();
      } else if (!extrinsic_from_config) {
        throw icgm::LoadError(
            "bag '" + bag_path + "' has wheel odometry but no base_link -> camera transform on "
            "/tf_static; give --extrinsic-from-config (fusion.base_to_camera_* of " + config_path +
            ") or --camera-only (ignore the wheels)");
      }
    } else if (source.base_to_camera) {
      options.fusion.base_to_camera = *source.base_to_camera;
    }
    // With --map the hybrid map runs behind the front end (loop closure, eq. 6.2 / 6.4) and the
    // trajectory is the corrected map trajectory; without it, the front end alone.
    slam_options.build_map = !map_path.empty();
    const std::string problem = icgm::tools::OutputFolderProblem({trajectory_path, gt_out_path});
    if (!problem.empty()) throw icgm::LoadError(problem);
    if (!map_path.empty()) {
      // Checked before processing: a long run must not end without its map.
      const icgm::Status writable = icgm::CheckMapWritable(map_path);
      if (!writable.ok()) throw icgm::LoadError(writable.reason());
      icgm::ReadMapSlamOptions(icgm::OptionReader::FromFile(map_config_path), &slam_options);
      if (pose_graph) slam_options.map.loop_closure.correction = icgm::LoopCorrection::kPoseGraph;
      slam_options.loop_closure = !no_loop_closure;
    }
    slam = std::make_unique<icgm::SlamSystem>(slam_options, source.intrinsics);
    const std::string& load_path = !merge_path.empty() ? merge_path : learned_path;
    if (!load_path.empty()) {
      const icgm::Status loaded = slam->Load(load_path, !merge_path.empty());
      if (!loaded.ok()) throw icgm::LoadError(loaded.reason());
      if (!slam->load_note().empty()) {
        std::fprintf(stderr, "icgm_slam_offline: warning: %s\n", slam->load_note().c_str());
      }
      std::printf("%s %s: %d keyframes in %zu sessions\n",
                  merge_path.empty() ? "localizing in" : "merging into", load_path.c_str(),
                  slam->map().size(), slam->map().sessions().size());
    }
    if (!learned_path.empty()) slam->SetMode(icgm::MapMode::kLocalization);
  } catch (const icgm::LoadError& e) {
    std::fprintf(stderr, "icgm_slam_offline: %s\n", e.what());
    return 1;
  } catch (const std::invalid_argument& e) {
    return UsageError(e.what());
  }

  const size_t total = max_frames > 0 ? std::min<size_t>(source.expected_frames,
                                                         static_cast<size_t>(max_frames))
                                      : source.expected_frames;
  icgm::ProgressBar progress(total, options.use_icgm ? "odometry (ICGM)" : "odometry (no ICGM)");
  FrameBook book;
  book.trend_on = options.residual_trend.on();
  if (!report_dir.empty()) {
    std::error_code ec;
    std::filesystem::create_directories(report_dir, ec);
    book.frames_csv.open(report_dir + "/frames.csv");
    if (!book.frames_csv) {
      std::fprintf(stderr, "icgm_slam_offline: cannot write %s/frames.csv\n", report_dir.c_str());
      return 1;
    }
    book.frames_csv << "stamp,source,features,matches,kept,matches_3d,inliers,inlier_ratio,"
                       "rmse_m,keyframe,features_ms,matching_ms,icgm_ms,registration_ms,total_ms,"
                       "dynamic_matches,dynamic_inliers,hypotheses,chosen_kind,chosen_score,"
                       "chosen_depth_agreeing,chosen_edges_agreeing,chosen_inliers,"
                       "chosen_dynamic_inliers,runner_up_score,status\n";
    book.trend_csv.open(report_dir + "/trend_votes.csv");
    book.trend_csv << "frame,reference,reference_x,reference_y,reference_mask_distance_px\n";
    book.hypotheses_csv.open(report_dir + "/hypotheses.csv");
    book.hypotheses_csv << "frame,reference,index,kind,chosen,inliers,dynamic_inliers,"
                           "depth_agreeing,edges_agreeing,score,prediction_distance,"
                           "median_depth_m,tx_m,ty_m,tz_m,rx_rad,ry_rad,rz_rad\n";
    book.matches_csv.open(report_dir + "/matches.csv");
    book.matches_csv << "frame,reference,ref_x,ref_y,cur_x,cur_y,cur_depth_m,inlier,"
                        "cur_mask_distance_px,ref_mask_distance_px\n";
  }
  icgm::SlamRunOptions run;
  run.max_frames = max_frames > 0 ? static_cast<size_t>(max_frames) : 0;
  run.wheel_odometry = source.wheel_odometry;
  // Wheel odometry received up to (slightly after) each frame, as a live system would have.
  run.wheel_lead_s = 0.05;
  run.on_frame = [&](size_t done, const icgm::SlamInputFrame& input,
                     const icgm::SlamFrameResult& r) {
    book.Add(input, r.frontend);
    if (r.keyframe && slam->mode() == icgm::MapMode::kLocalization && !r.update.loop_closed) {
      const std::string& why = r.update.loop.status.reason();
      ++book.unlocated[why.substr(0, why.find(':', why.find(':') + 1))];
    }
    progress.Update(done);
  };
  icgm::SlamFrameSource frames = source.frames;
  if (oracle_static) {
    // Diagnosis only: the walkers' depth is blanked, so their features cannot register.
    frames = [inner = source.frames](icgm::SlamInputFrame* f, std::string* error) {
      if (!inner(f, error)) return false;
      if (!f->dynamic_mask.empty()) {
        f->depth_m = f->depth_m.clone();
        f->depth_m.setTo(std::numeric_limits<float>::quiet_NaN(), f->dynamic_mask);
      }
      return true;
    };
  }
  const icgm::SlamRunReport report = icgm::RunSlam(slam.get(), frames, run);
  // Input that ended early (a corrupt bag) keeps what was built, and is not a success.
  const std::string ended_early = icgm::tools::InputEndedEarly(report.frames, report.input_error);
  if (ended_early.empty()) {
    progress.Finish();
  } else {
    progress.Finish(report.frames);
    std::fprintf(stderr, "icgm_slam_offline: %s\n", ended_early.c_str());
  }
  const size_t skipped_frames = *source.skipped_frames;
  if (book.trajectory.empty()) {
    std::fprintf(stderr, "icgm_slam_offline: no frames processed\n");
    return 1;
  }
  icgm::Trajectory trajectory = book.trajectory;
  // The front end's own trajectory, kept for its ATE beside the map's.
  icgm::Trajectory frontend_trajectory;
  if (!map_path.empty()) {
    frontend_trajectory = book.trajectory;
    // Saved first, then refined and saved again (SaveMap): whatever happens in the refinement,
    // the map built so far is kept (atomic save).
    std::string detail;
    const icgm::Status saved =
        slam->SaveMap(map_path, refine || slam->options().map_refinement.enabled, &detail);
    if (!saved.ok()) {
      std::fprintf(stderr, "icgm_slam_offline: map not saved: %s\n", saved.reason().c_str());
      return 1;
    }
    trajectory = slam->MapTrajectory();
    std::printf("map: %d keyframes, %zu loop closures, %zu relocalizations; %s\n",
                slam->map().size(), slam->loop_closures().size(), slam->relocalizations(),
                detail.c_str());
  }
  try {
    icgm::WriteTumTrajectory(trajectory_path, trajectory);
    if (!gt_out_path.empty()) {
      if (source.groundtruth.empty()) {
        std::fprintf(stderr, "icgm_slam_offline: --gt-out: the input has no ground truth\n");
      } else {
        icgm::WriteTumTrajectory(gt_out_path, source.groundtruth);
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
      slam->frontend().num_keyframes(), options.use_icgm ? "on" : "off", threads);
  if (skipped_frames > 0) {
    add("skipped %zu unreadable frames (see the warnings above)\n", skipped_frames);
  }
  add("%-22s %8s %8s %8s   (wall time unless noted)\n", "stage [ms]", "mean", "median", "p95");
  const icgm::SlamStageTimes& times = report.times;
  const std::pair<const char*, const std::vector<double>*> stages[] = {
      {"features", &times.features},
      {"matching", &times.matching},
      {"icgm", &times.icgm},
      {"registration", &times.registration},
      {"fusion", &times.fusion},
      {"front end (4 stages)", &book.front_end_ms},
      {"total per frame", &times.frame_total},
      {"total, thread CPU", &times.thread_cpu}};
  for (const auto& [name, v] : stages) {
    const Summary s = Summarize(*v);
    add("%-22s %8.2f %8.2f %8.2f\n", name, s.mean, s.median, s.p95);
  }
  if (!map_path.empty()) {
    const Summary s = Summarize(times.map_update);
    add("%-22s %8.2f %8.2f %8.2f   (per keyframe)\n", "map update", s.mean, s.median, s.p95);
  }
  const icgm::FusionStats& fs = slam->frontend().fusion_stats();
  add("motion from vision: %.1f%% of frames, %.1f%% of distance (%.3f m)\n",
      100.0 * fs.VisionShareByFrames(), 100.0 * fs.VisionShareByDistance(), fs.total_distance_m());
  for (size_t k = 0; k < icgm::kNumMotionSources; ++k) {
    add("  %-18s %6zu frames %8.3f m\n", icgm::MotionSourceName(static_cast<icgm::MotionSource>(k)),
        fs.frames[k], fs.distance_m[k]);
  }
  if (!book.reprojection_rms_px.empty()) {
    const Summary s = Summarize(book.reprojection_rms_px);
    add("registration reprojection rms [px]: mean %.3f, median %.3f, p95 %.3f (%zu frames)\n",
        s.mean, s.median, s.p95, book.reprojection_rms_px.size());
  }
  if (book.prior_gated > 0) {
    add("  registration gave way to the constant-velocity prediction (prior gate) %zu x\n",
        book.prior_gated);
  }
  if (book.velocity_gate_rejected + book.velocity_gate_dropped_prior > 0) {
    add("  velocity gate: %zu registered steps set aside, %zu predictions dropped\n",
        book.velocity_gate_rejected, book.velocity_gate_dropped_prior);
  }
  if (book.prior_reset > 0) add("  motion prior reset at %zu frames\n", book.prior_reset);
  if (book.registrations_agreed + book.keyframes_postponed > 0) {
    std::vector<double> spreads = book.registration_spreads_m;
    std::sort(spreads.begin(), spreads.end());
    add("  registrations compared at %zu frames (spread median %.1f mm), agreed at %zu, %zu new "
        "keyframes postponed\n",
        spreads.size(), spreads.empty() ? NAN : 1000.0 * spreads[spreads.size() / 2],
        book.registrations_agreed, book.keyframes_postponed);
  }
  if (book.anchor_linked > 0) {
    add("  pose corrected by an anchor keyframe's registration at %zu frames\n",
        book.anchor_linked);
  }
  if (book.velocity_rebased > 0) {
    add("  velocity history rebased at %zu of %zu new keyframes\n", book.velocity_rebased,
        book.new_keyframes);
  }
  if (book.prior_released > 0) {
    add("  motion prior released at %zu frames (registered to the previous frame, in a row)\n",
        book.prior_released);
  }
  for (const auto& [why, n] : book.failures) add("  registration failed %4zu x: %s\n", n, why.c_str());
  for (const auto& [why, n] : report.map_problems) add("  keyframe refused %4zu x: %s\n", n, why.c_str());
  for (const auto& [why, n] : book.unlocated) add("  keyframe not located %4zu x: %s\n", n, why.c_str());
  if (book.trend_voted > 0) {
    add("  residual trend voted out %zu reference keypoints", book.trend_voted);
    if (book.trend_voted_checked > 0) {
      add(", %.1f%% of %zu on walkers (ground-truth mask)",
          100.0 * book.trend_voted_on_walkers / book.trend_voted_checked, book.trend_voted_checked);
    }
    add("\n");
  }
  if (book.masked_frames > 0) {
    const icgm::tools::DynamicMatchCount& d = book.dynamic_total;
    add("matches on pedestrians: %.2f%% of registration matches (%zu / %zu), %.2f%% of inliers "
        "(%zu / %zu)\n",
        100.0 * d.MatchShare(), d.dynamic_matches, d.matches, 100.0 * d.InlierShare(),
        d.dynamic_inliers, d.inliers);
    add("  frames with pedestrian inliers %zu of %zu, with mostly pedestrian inliers %zu\n",
        book.frames_with_dynamic_inliers, book.masked_frames, book.frames_dynamic_majority);
  }
  if (!source.groundtruth.empty()) {
    icgm::TrajectoryEvaluation ev;
    const icgm::Status s = icgm::EvaluateTrajectory(source.groundtruth, trajectory,
                                                    icgm::TrajectoryEvalOptions(), &ev);
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
          icgm::EvaluateTrajectory(source.groundtruth, frontend_trajectory,
                                   icgm::TrajectoryEvalOptions(), &fev)
              .ok()) {
        add("front end ATE rmse %.4f m (before the map's loop correction)\n", fev.ate.rmse);
      }
      add("ATE rmse %.4f m, mean %.4f m, max %.4f m (%zu poses); RPE %.4f m/s, %.3f deg/s\n",
          ev.ate.rmse, ev.ate.mean, ev.ate.max, ev.ate.count, ev.rpe_translation_m_per_s.rmse,
          ev.rpe_rotation_deg_per_s.rmse);
    } else {
      add("ATE not available: %s\n", s.reason().c_str());
      icgm::Trajectory gt = source.groundtruth;
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
  // The outputs cover the frames before the failure only.
  if (!ended_early.empty()) return icgm::tools::Failure(kTool, ended_early);
  return 0;
}
