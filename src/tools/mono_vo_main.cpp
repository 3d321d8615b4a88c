// icgm_mono_vo: monocular visual odometry (core/mono) on the colour images of a TUM folder or
// of a simulator scenario rendered in process (depth only measures the map's scale), with or
// without ICGM;
// prints the Sim(3) ATE, that error in % of the distance travelled (thesis Table 6.5), the
// inlier ratio and the time per frame on one core.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <ctime>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include <opencv2/core.hpp>
#include <opencv2/core/utility.hpp>

#include "core/common/progress_bar.h"
#include "core/common/sample_summary.h"
#include "core/common/status.h"
#include "core/common/thread_cpu_time.h"
#include "core/dataset/camera_options.h"
#include "core/dataset/trajectory.h"
#include "core/dataset/tum_dataset.h"
#include "core/eval/trajectory_plot.h"
#include "core/mono/mono_evaluation.h"
#include "core/mono/mono_pose_gaps.h"
#include "core/mono/mono_odometry.h"
#include "core/mono/mono_options.h"
#include "core/sim/frame_prefetcher.h"
#include "core/sim/sim_export.h"
#include "core/sim/sim_options.h"
#include "core/sim/simulator.h"
#include "tools/cli_args.h"
#include "tools/dynamic_match_stats.h"
#include "tools/offline_sources.h"

namespace {

constexpr char kUsage[] =
    "usage: icgm_mono_vo (--tum DIR | --sim SCENARIO.yaml | --bag FILE) [--no-icgm]\n"
    "                    [--output traj.txt] [--plot out.png] [--config config/mono.yaml]\n"
    "                    [--camera camera.yaml] [--max-frames N] [--sim-seed N] [--no-wheels]\n"
    "                    [--log frames.csv] [--segment-frames N] [--rng-seed N] [--ransac-seed N]\n"
    "  Monocular visual odometry (ICGM matches -> essential matrix -> PnP on a triangulated\n"
    "  local map with windowed bundle adjustment) on the colour images only.\n"
    "  --tum DIR         TUM RGB-D folder (rgb.txt, groundtruth.txt); --camera defaults to\n"
    "                    config/camera/tum_fr1.yaml.\n"
    "  --sim SCENARIO    simulator scenario rendered in process (depth only for the map scale\n"
    "                    by depth); a wheeled\n"
    "                    robot's odometry gives the metric scale unless --no-wheels.\n"
    "  --bag FILE        rosbag read as icgm_slam_offline reads it (colour images, camera_info\n"
    "                    or --camera, ground truth, wheel odometry with the /tf_static\n"
    "                    extrinsic); needs the build with the ROS bridge.\n"
    "  --no-icgm         plain ratio-test matches (comparison baseline).\n"
    "  --output FILE     estimated camera trajectory (TUM format).\n"
    "  --plot FILE       PNG of ground truth vs. the Sim(3)-aligned estimate.\n"
    "  --log FILE        one CSV line per frame (state, matches, inliers, times, status).\n"
    "  --segment-frames N  also the Sim(3) ATE and scale of each run of N input frames aligned\n"
    "                    on its own (scale drift shows as changing scales).\n"
    "  --rng-seed N      seed of ICGM's seed-pair draws instead of the fixed one: repeats of a\n"
    "                    real input with ICGM (OpenCV's RANSAC draws from a fixed seed of its\n"
    "                    own, so a run without ICGM repeats exactly).\n"
    "  --ransac-seed N   mono.ransac_order_seed: RANSAC (essential matrix, PnP) receives the\n"
    "                    matches in an order drawn from N: repeats of a run in either mode.\n"
    "  Prints the Sim(3) ATE, the ATE in % of the distance travelled, the relative error over\n"
    "  segments of 10-50 % of the path (KITTI-style, in % of the segment's length), the inlier\n"
    "  ratio and the time per frame and per stage (thread CPU time, OpenCV on one thread:\n"
    "  features, matching, ICGM, geometry = essential matrix or PnP with the projection search,\n"
    "  mapping = keyframes, triangulation, bundle adjustment); also the ATE of each map aligned\n"
    "  on its own (one Sim(3) per map, RMSE over all their poses), each map's scale (whole,\n"
    "  first and last 20 poses), the jump of the local scale at each reset, and the error with\n"
    "  every map rescaled to the first's units by its own scale and by the local jumps alone\n"
    "  (scale carried exactly over the resets). With depth images (TUM folder, simulator) also\n"
    "  each map's own scale from them (depth image over map depth of the tracked points, metres\n"
    "  per map unit) over its first and last 20 tracked frames, and the error with every step\n"
    "  in metres by its map's scale from depth (each map's scale held exactly).";
constexpr icgm::tools::ToolInfo kTool{"icgm_mono_vo", kUsage};

int UsageError(const std::string& message) { return icgm::tools::UsageError(kTool, message); }

std::vector<cv::Point2f> ToCv(const std::vector<Eigen::Vector2d>& pixels) {
  std::vector<cv::Point2f> out;
  out.reserve(pixels.size());
  for (const auto& p : pixels) out.emplace_back(p.x(), p.y());
  return out;
}

using icgm::ThreadCpuMs;

struct Request {
  std::string tum_dir, sim_path, bag_path, output, plot, log;
  std::string config = std::string(ICGM_CONFIG_DIR) + "/mono.yaml";
  std::string camera = std::string(ICGM_CONFIG_DIR) + "/camera/tum_fr1.yaml";
  bool no_icgm = false;
  bool no_wheels = false;
  bool camera_given = false;
  int max_frames = -1;
  int segment_frames = 0;
  std::optional<int> sim_seed;
  std::optional<int> rng_seed;
  std::optional<int> ransac_seed;
};

// One colour image and, with wheels, the odometry sample of its instant.
struct InputFrame {
  icgm::Time stamp;
  cv::Mat bgr;
  std::optional<icgm::Pose3> odom_base;
  icgm::Trajectory wheel_samples;  // odometry samples (odom -> base) up to the stamp
  cv::Mat dynamic_mask;            // simulator: 255 where a pedestrian is the visible surface
  cv::Mat depth_m;                 // the input's depth image (CV_32FC1 metres), if it has one
};

// The run with each step between consecutive poses of a map multiplied by that map's scale
// from the depth images (`scales`, per pose, NaN none; the median of the valid ones among the 9
// poses about it, else the last one used), a new map continuing from where the one before
// ended: the trajectory as if every map had held its scale exactly and every reset had carried
// it, with the errors of the estimated motion kept.
icgm::Trajectory StepsInMetres(const std::vector<icgm::Trajectory>& maps,
                               const std::vector<std::vector<double>>& scales) {
  icgm::Trajectory out;
  Eigen::Vector3d at = Eigen::Vector3d::Zero();
  double scale = 1.0;
  for (size_t m = 0; m < maps.size() && m < scales.size(); ++m) {
    const icgm::Trajectory& poses = maps[m];
    for (size_t i = 0; i < poses.size() && i < scales[m].size(); ++i) {
      std::vector<double> near;
      for (size_t j = i >= 4 ? i - 4 : 0; j <= i + 4 && j < scales[m].size(); ++j) {
        if (std::isfinite(scales[m][j])) near.push_back(scales[m][j]);
      }
      if (!near.empty()) {
        std::nth_element(near.begin(), near.begin() + near.size() / 2, near.end());
        scale = near[near.size() / 2];
      }
      if (i > 0) at += scale * (poses[i].pose.translation() - poses[i - 1].pose.translation());
      // A re-initialization's reference frame repeats a stamp the map before already gave.
      if (!out.empty() && poses[i].stamp <= out.back().stamp) continue;
      icgm::Pose3 p = poses[i].pose;
      p.translation() = at;
      out.push_back({poses[i].stamp, p});
    }
  }
  return out;
}

// Median of the first and of the last `n` values (or of all when fewer).
std::pair<double, double> EdgeMedians(std::vector<double> v, size_t n) {
  const auto median = [](std::vector<double> x) {
    std::nth_element(x.begin(), x.begin() + x.size() / 2, x.end());
    return x[x.size() / 2];
  };
  const size_t k = std::min(n, v.size());
  return {median({v.begin(), v.begin() + k}), median({v.end() - k, v.end()})};
}
using NextFrame = std::function<bool(InputFrame*)>;

struct Source {
  icgm::CameraIntrinsics intrinsics;
  icgm::Trajectory groundtruth;
  std::optional<icgm::Pose3> base_to_camera;
  size_t frames = 0;
  NextFrame next;
  // Frames skipped because their image could not be read (warned and counted, not fed to the
  // odometry, so not counted as lost).
  std::shared_ptr<size_t> skipped = std::make_shared<size_t>(0);
};

Source OpenTum(const Request& r) {
  Source s;
  auto dataset = std::make_shared<icgm::TumDataset>(
      icgm::TumDataset::Open(r.tum_dir, icgm::LoadCameraIntrinsics(r.camera)));
  s.intrinsics = dataset->intrinsics();
  s.groundtruth = dataset->groundtruth();
  s.frames = dataset->size();
  auto i = std::make_shared<size_t>(0);
  s.next = [dataset, i, skipped = s.skipped](InputFrame* f) {
    // An unreadable image skips its frame (as in icgm_slam_offline), not the end of the run.
    for (;; ++*i, ++*skipped) {
      if (*i >= dataset->size()) return false;
      try {
        f->bgr = dataset->LoadBgr(*i);
        break;
      } catch (const icgm::LoadError& e) {
        std::fprintf(stderr, "\nicgm_mono_vo: warning: frame %zu skipped: %s\n", *i, e.what());
      }
    }
    f->stamp = dataset->frame(*i).stamp;
    try {
      f->depth_m = dataset->LoadDepthM(*i);  // only for the map scale by depth
    } catch (const icgm::LoadError&) {
      f->depth_m = cv::Mat();
    }
    ++*i;
    return true;
  };
  return s;
}

Source OpenSim(const Request& r) {
  Source s;
  icgm::sim::SimOptions options = icgm::sim::LoadSimOptions(r.sim_path);
  if (r.sim_seed) options.seed = *r.sim_seed;
  auto sim = std::make_shared<icgm::sim::Simulator>(options);
  s.intrinsics = sim->intrinsics();
  s.groundtruth = icgm::sim::CameraGroundTruth(*sim);
  const bool wheels = sim->has_wheel_odometry() && !r.no_wheels;
  if (wheels) s.base_to_camera = sim->base_to_camera();
  s.frames = sim->size();
  auto prefetcher = std::make_shared<icgm::sim::FramePrefetcher>(*sim);
  s.next = [sim, prefetcher, wheels](InputFrame* f) {
    icgm::sim::SimFrame frame;
    if (!prefetcher->Next(&frame)) return false;
    f->stamp = frame.stamp;
    f->bgr = frame.bgr;
    f->dynamic_mask = frame.dynamic_mask;
    f->depth_m = frame.depth_m;
    if (wheels) f->odom_base = frame.odometry.T_odom_base;
    return true;
  };
  return s;
}

// Each run of `segment` input frames aligned on its own: ATE, % of its distance and the Sim(3)
// scale (metres per map unit), so scale drift and the segments that hold the error stand out.
void PrintSegments(const icgm::Trajectory& groundtruth, const icgm::Trajectory& estimate,
                   const std::vector<icgm::Time>& stamps, int segment) {
  for (size_t first = 0; first < stamps.size(); first += segment) {
    const size_t last = std::min(stamps.size(), first + segment) - 1;
    icgm::Trajectory part;
    for (const auto& p : estimate) {
      if (p.stamp >= stamps[first] && p.stamp <= stamps[last]) part.push_back(p);
    }
    icgm::MonoEvaluation m;
    const icgm::Status s = part.size() < 10
                               ? icgm::Status::Error(std::to_string(part.size()) + " poses")
                               : icgm::EvaluateMonoTrajectory(groundtruth, part, 0.02, &m);
    if (!s.ok()) {
      std::printf("segment %4zu-%4zu    not aligned: %s\n", first, last, s.reason().c_str());
      continue;
    }
    std::printf("segment %4zu-%4zu    %3zu poses  ATE %.4f m  %.2f %% of %.2f m  scale %.4f\n",
                first, last, part.size(), m.evaluation.ate.rmse, m.error_percent, m.distance_m,
                m.scale);
  }
}

// A bag through the offline tool's reader (tools/offline_sources.h); the wheel odometry samples
// up to each frame's stamp go with that frame.
Source OpenBag(const Request& r) {
  std::optional<icgm::CameraIntrinsics> fallback;
  if (r.camera_given) fallback = icgm::LoadCameraIntrinsics(r.camera);
  auto bag = std::make_shared<icgm::tools::OfflineSource>(
      icgm::tools::OpenBagSource(r.bag_path, fallback));
  Source s;
  s.intrinsics = bag->intrinsics;
  s.groundtruth = bag->groundtruth;
  const bool wheels = bag->base_to_camera && !bag->wheel_odometry.empty() && !r.no_wheels;
  if (wheels) s.base_to_camera = bag->base_to_camera;
  s.frames = bag->expected_frames;
  auto next_wheel = std::make_shared<size_t>(0);
  s.next = [bag, next_wheel, wheels](InputFrame* f) {
    icgm::SlamInputFrame frame;
    std::string error;
    if (!bag->frames(&frame, &error)) {
      if (!error.empty()) std::fprintf(stderr, "icgm_mono_vo: %s\n", error.c_str());
      return false;
    }
    f->stamp = frame.stamp;
    f->bgr = frame.bgr;
    f->odom_base.reset();
    f->wheel_samples.clear();
    while (wheels && *next_wheel < bag->wheel_odometry.size() &&
           bag->wheel_odometry[*next_wheel].stamp <= frame.stamp) {
      f->wheel_samples.push_back(bag->wheel_odometry[(*next_wheel)++]);
    }
    return true;
  };
  return s;
}

int Run(const Request& r) {
  cv::setNumThreads(1);
  icgm::MonoOptions options = icgm::LoadMonoOptions(r.config);
  if (r.no_icgm) options.vo.use_icgm = false;
  if (r.rng_seed) options.icgm.rng_seed = static_cast<uint64_t>(*r.rng_seed);
  if (r.ransac_seed) options.vo.ransac_order_seed = *r.ransac_seed;
  Source source = !r.bag_path.empty() ? OpenBag(r) : r.tum_dir.empty() ? OpenSim(r) : OpenTum(r);
  icgm::MonoOdometry vo(options, source.intrinsics);
  if (source.base_to_camera) vo.SetBaseToCamera(*source.base_to_camera);

  size_t total = source.frames;
  if (r.max_frames > 0 && static_cast<size_t>(r.max_frames) < total) total = r.max_frames;
  icgm::ProgressBar bar(total, options.vo.use_icgm ? "mono vo (icgm)" : "mono vo (no icgm)");
  icgm::Trajectory estimate;
  std::vector<icgm::Trajectory> maps;  // the poses of each map (a reset starts a new one)
  std::vector<double> cpu_ms, inlier_ratio;
  icgm::MonoStageTimes stage_sum;  // CPU per stage, summed over the frames
  size_t with_pose = 0, resets = 0, scale_known_frames = 0;
  icgm::MonoPoseGapCounter gaps;  // frames without a pose, by cause
  icgm::tools::DynamicMatchCount walkers;  // simulator: matches and inliers on pedestrians
  // ... the tracked pose's inliers (after the local map's projection) and new map points
  icgm::tools::DynamicMatchCount tracked_walkers, new_point_walkers;
  // ... the ratio-test matches to the newest keyframe with and without a map point, and which
  // of them ICGM kept (the "inliers" of the count)
  icgm::tools::DynamicMatchCount point_matches, candidate_matches;
  // ... the matches with the frame track_icgm_baseline_frames before (kept: in ICGM's group),
  // and the correspondences not given to PnP for it
  icgm::tools::DynamicMatchCount long_baseline_matches, long_baseline_dropped;
  size_t long_baseline_gated = 0;
  // ... the map points deleted as moving and the new points not added
  icgm::tools::DynamicMatchCount culled_walkers, rejected_walkers;
  // ... the map points ICGM rejected, and those the projection search matched again
  icgm::tools::DynamicMatchCount icgm_rejected_walkers, readmitted_walkers;
  size_t icgm_rejected_points = 0, readmitted_points = 0;
  icgm::tools::DynamicMatchCount verified_walkers;  // inliers: the verified correspondences
  size_t verified_frames = 0;
  size_t culled_points = 0, rejected_new_points = 0;
  size_t good_relocalized_frames = 0;
  // rotation_only_parallax_deg: frames posed by the rotation alone, the parallax measured.
  size_t rotation_only_frames = 0, parallax_frames = 0;
  std::vector<double> parallaxes;
  size_t relocalized_frames = 0, duplicate_frames = 0, duplicate_points = 0;
  // scene_depth_band: keyframes whose map was scaled, and the factors' product and extremes.
  size_t depth_holds = 0;
  double depth_hold_product = 1.0, depth_hold_min = 1.0, depth_hold_max = 1.0;
  // Inputs with a depth image: metres per map unit at each tracked frame, per map.
  std::vector<std::vector<double>> depth_scales;
  // ... and per pose of each map (NaN: none at that pose).
  std::vector<std::vector<double>> pose_depth_scales;
  std::FILE* log = nullptr;
  if (!r.log.empty()) {
    log = std::fopen(r.log.c_str(), "w");
    if (!log) return icgm::tools::Failure(kTool, "cannot write " + r.log);
    std::fprintf(log,
                 "frame,stamp,state,pose,keyframe,reset,features,matches,kept,inliers,"
                 "map_points,total_ms,features_ms,matching_ms,icgm_ms,geometry_ms,"
                 "mapping_ms,prior_thr,relocalized,tracked_on_walkers,new_points,new_on_walkers,"
                 "extra_new_points,status\n");
  }
  InputFrame frame;
  std::vector<icgm::Time> stamps;  // of every input frame
  size_t n = 0;
  while (n < total && source.next(&frame)) {
    stamps.push_back(frame.stamp);
    if (frame.odom_base) vo.AddWheelOdometry(frame.stamp, *frame.odom_base);
    for (const auto& w : frame.wheel_samples) vo.AddWheelOdometry(w.stamp, w.pose);
    const double c0 = ThreadCpuMs();
    const icgm::MonoFrameResult res = vo.ProcessFrame(frame.stamp, frame.bgr);
    cpu_ms.push_back(ThreadCpuMs() - c0);
    gaps.Add(res);
    stage_sum.features_ms += res.times.features_ms;
    stage_sum.matching_ms += res.times.matching_ms;
    stage_sum.icgm_ms += res.times.icgm_ms;
    stage_sum.geometry_ms += res.times.geometry_ms;
    stage_sum.mapping_ms += res.times.mapping_ms;
    if (res.initialized) {
      estimate.push_back({res.reference_stamp, res.reference_world_camera});
      maps.push_back({{res.reference_stamp, res.reference_world_camera}});
      depth_scales.emplace_back();
      pose_depth_scales.push_back({std::nan("")});
    }
    const auto scale =
        icgm::MapScaleFromDepth(frame.depth_m, res.tracked_pixels, res.tracked_depths);
    if (scale && !depth_scales.empty()) depth_scales.back().push_back(*scale);
    if (res.has_pose) {
      estimate.push_back({res.stamp, res.world_camera});
      if (!maps.empty()) {
        maps.back().push_back({res.stamp, res.world_camera});
        pose_depth_scales.back().push_back(scale.value_or(std::nan("")));
      }
      ++with_pose;
      if (res.scale_known) ++scale_known_frames;
      if (res.num_icgm_kept > 0) inlier_ratio.push_back(res.inlier_ratio);
    }
    if (res.reset) ++resets;
    if (!frame.dynamic_mask.empty()) {
      std::vector<cv::Point2f> pixels;
      for (const auto& p : res.robust_pixels) pixels.emplace_back(p.x(), p.y());
      walkers += icgm::tools::CountDynamicMatches(frame.dynamic_mask, pixels, res.robust_inliers);
      tracked_walkers +=
          icgm::tools::CountDynamicMatches(frame.dynamic_mask, ToCv(res.tracked_pixels), {});
      new_point_walkers +=
          icgm::tools::CountDynamicMatches(frame.dynamic_mask, ToCv(res.new_point_pixels), {});
      point_matches += icgm::tools::CountDynamicMatches(
          frame.dynamic_mask, ToCv(res.to_last_point_pixels), res.to_last_point_kept);
      candidate_matches += icgm::tools::CountDynamicMatches(
          frame.dynamic_mask, ToCv(res.to_last_candidate_pixels), res.to_last_candidate_kept);
      long_baseline_matches += icgm::tools::CountDynamicMatches(
          frame.dynamic_mask, ToCv(res.long_baseline_pixels), res.long_baseline_kept);
      long_baseline_dropped += icgm::tools::CountDynamicMatches(
          frame.dynamic_mask, ToCv(res.long_baseline_dropped_pixels), {});
      long_baseline_gated += res.long_baseline_gated;
      culled_walkers +=
          icgm::tools::CountDynamicMatches(frame.dynamic_mask, ToCv(res.culled_pixels), {});
      readmitted_walkers += icgm::tools::CountDynamicMatches(
          frame.dynamic_mask, ToCv(res.icgm_rejected_readmitted_pixels), {});
      icgm_rejected_walkers +=
          icgm::tools::CountDynamicMatches(frame.dynamic_mask, ToCv(res.icgm_rejected_pixels), {});
      rejected_walkers += icgm::tools::CountDynamicMatches(frame.dynamic_mask,
                                                           ToCv(res.rejected_new_point_pixels), {});
      if (!res.robust_verified.empty()) {
        verified_walkers +=
            icgm::tools::CountDynamicMatches(frame.dynamic_mask, pixels, res.robust_verified);
      }
    }
    verified_frames += res.pnp_on_verified;
    culled_points += res.culled_points;
    icgm_rejected_points += res.icgm_rejected_points;
    readmitted_points += res.icgm_rejected_readmitted_pixels.size();
    relocalized_frames += res.relocalized;
    good_relocalized_frames += res.relocalized_on_good_keyframe;
    rotation_only_frames += res.rotation_only;
    if (res.parallax_deg > 0.0) {
      ++parallax_frames;
      parallaxes.push_back(res.parallax_deg);
    }
    duplicate_frames += res.duplicate_points_skipped > 0;
    duplicate_points += res.duplicate_points_skipped;
    rejected_new_points += res.rejected_new_points;
    if (res.scene_depth_scale != 1.0) {
      ++depth_holds;
      depth_hold_product *= res.scene_depth_scale;
      depth_hold_min = std::min(depth_hold_min, res.scene_depth_scale);
      depth_hold_max = std::max(depth_hold_max, res.scene_depth_scale);
    }
    if (log) {
      // Simulator: the tracked pose's inliers and the new map points on pedestrians (-1: no
      // mask).
      long tracked_on_walkers = -1, new_on_walkers = -1;
      if (!frame.dynamic_mask.empty()) {
        tracked_on_walkers = static_cast<long>(
            icgm::tools::CountDynamicMatches(frame.dynamic_mask, ToCv(res.tracked_pixels), {})
                .dynamic_matches);
        new_on_walkers = static_cast<long>(
            icgm::tools::CountDynamicMatches(frame.dynamic_mask, ToCv(res.new_point_pixels), {})
                .dynamic_matches);
      }
      std::fprintf(
          log,
          "%zu,%.6f,%s,%d,%d,%d,%zu,%zu,%zu,%zu,%zu,%.2f,%.2f,%.2f,%.2f,%.2f,%.2f,%.3f,%d,%ld,%zu,"
          "%ld,%zu,\"%s\"\n",
          res.frame_index, res.stamp.seconds(), icgm::MonoStateName(res.state), res.has_pose,
          res.new_keyframe, res.reset, res.num_features, res.num_matches, res.num_icgm_kept,
          res.num_inliers, res.map_points, res.times.total_ms, res.times.features_ms,
          res.times.matching_ms, res.times.icgm_ms, res.times.geometry_ms, res.times.mapping_ms,
          res.prior_threshold, res.relocalized, tracked_on_walkers, res.new_point_pixels.size(),
          new_on_walkers, res.extra_new_points, res.status.ok() ? "" : res.status.reason().c_str());
    }
    bar.Update(++n);
  }
  bar.Finish();
  if (log) std::fclose(log);
  icgm::SortByStamp(&estimate);
  // A frame that was the reference of two initializations appears twice: keep the later pose.
  icgm::Trajectory unique;
  for (const auto& p : estimate) {
    if (!unique.empty() && unique.back().stamp == p.stamp) {
      unique.back() = p;
    } else {
      unique.push_back(p);
    }
  }
  estimate = unique;
  if (!r.output.empty()) icgm::WriteTumTrajectory(r.output, estimate);

  const icgm::SampleSummary time = icgm::Summarize(cpu_ms);
  const icgm::SampleSummary inliers = icgm::Summarize(inlier_ratio);
  std::printf("input                %s\n", (!r.bag_path.empty() ? r.bag_path
                                            : r.tum_dir.empty() ? r.sim_path
                                                                : r.tum_dir)
                                               .c_str());
  std::printf("matching             %s\n", options.vo.use_icgm ? "ICGM" : "ratio test only");
  std::printf("frames               %zu, with pose %zu (%.1f%%), keyframes %zu, resets %zu\n", n,
              with_pose, n ? 100.0 * with_pose / n : 0.0, vo.num_keyframes(), resets);
  if (*source.skipped > 0) {
    std::printf("skipped              %zu unreadable frames (see the warnings above)\n",
                *source.skipped);
  }
  const icgm::MonoFramesWithoutPose no_pose = gaps.Counts();
  std::printf(
      "without pose         %zu frames: %zu before the first map, %zu lost (map kept), %zu lost "
      "then reset, %zu re-initializing\n",
      no_pose.total(), no_pose.not_initialized, no_pose.lost, no_pose.lost_then_reset,
      no_pose.reinitializing);
  std::printf("scale                %s\n",
              scale_known_frames > 0 ? "metric (wheel odometry)" : "unknown (monocular)");
  std::printf("inlier ratio         mean %.3f  median %.3f\n", inliers.mean, inliers.median);
  if (walkers.matches > 0) {
    std::printf(
        "on pedestrians       %.2f %% of %zu matches to the geometry, %.2f %% of %zu "
        "inliers\n",
        100.0 * walkers.MatchShare(), walkers.matches, 100.0 * walkers.InlierShare(),
        walkers.inliers);
    std::printf(
        "                     %.2f %% of %zu inliers of the tracked poses, %.2f %% of %zu "
        "new map points\n",
        100.0 * tracked_walkers.MatchShare(), tracked_walkers.matches,
        100.0 * new_point_walkers.MatchShare(), new_point_walkers.matches);
    // Ratio-test matches to the newest keyframe that ICGM dropped, static and on walkers.
    const auto dropped = [](const char* what, const icgm::tools::DynamicMatchCount& c) {
      const size_t dropped_walkers = c.dynamic_matches - c.dynamic_inliers;
      const size_t dropped_static =
          (c.matches - c.dynamic_matches) - (c.inliers - c.dynamic_inliers);
      std::printf(
          "%s %zu (%.2f %% on pedestrians), kept %zu (%.2f %%), dropped %zu static + %zu on "
          "pedestrians\n",
          what, c.matches, 100.0 * c.MatchShare(), c.inliers, 100.0 * c.InlierShare(),
          dropped_static, dropped_walkers);
    };
    dropped("to newest keyframe   with map point", point_matches);
    dropped("                     without (new point candidates)", candidate_matches);
    if (long_baseline_matches.matches > 0) {
      dropped("long-baseline ICGM   matches", long_baseline_matches);
      std::printf(
          "                     %zu correspondences not given to PnP (%.2f %% on pedestrians)\n",
          long_baseline_dropped.matches, 100.0 * long_baseline_dropped.MatchShare());
      std::printf("                     %zu frames skipped (camera moved too far against the depth)\n",
                  long_baseline_gated);
    }
  }
  if (options.vo.scene_depth_band > 0.0) {
    std::printf(
        "scene depth hold     map scaled at %zu keyframes, factors %.3f-%.3f, product %.3g\n",
        depth_holds, depth_hold_min, depth_hold_max, depth_hold_product);
  }
  if (culled_points > 0 || rejected_new_points > 0) {
    std::printf("moving map points    %zu deleted, %zu new points not added\n", culled_points,
                rejected_new_points);
    if (culled_walkers.matches + rejected_walkers.matches > 0) {
      std::printf(
          "                     on pedestrians: %.2f %% of the deleted, %.2f %% of the "
          "not added\n",
          100.0 * culled_walkers.MatchShare(), 100.0 * rejected_walkers.MatchShare());
    }
  }
  if (icgm_rejected_points > 0) {
    std::printf("ICGM-rejected points %zu", icgm_rejected_points);
    if (icgm_rejected_walkers.matches > 0) {
      std::printf(" (%.2f %% on pedestrians)", 100.0 * icgm_rejected_walkers.MatchShare());
    }
    std::printf(", %zu matched again by the projection search", readmitted_points);
    if (readmitted_walkers.matches > 0) {
      std::printf(" (%.2f %% on pedestrians)", 100.0 * readmitted_walkers.MatchShare());
    }
    std::printf("\n");
  }
  if (options.vo.pnp_verified_min_keyframes > 0) {
    std::printf("verified map points  their own PnP pose taken in %zu frames", verified_frames);
    if (verified_walkers.matches > 0) {
      std::printf("; %.2f %% of %zu verified correspondences on pedestrians, %.2f %% of all %zu",
                  100.0 * verified_walkers.InlierShare(), verified_walkers.inliers,
                  100.0 * verified_walkers.MatchShare(), verified_walkers.matches);
    }
    std::printf("\n");
  }
  std::printf(
      "relocalized frames   %zu (%zu on the last good keyframe), %zu with map points not matched "
      "twice (%zu points skipped)\n",
      relocalized_frames, good_relocalized_frames, duplicate_frames, duplicate_points);
  if (options.vo.rotation_only_parallax_deg > 0.0) {
    double median = 0.0;
    if (!parallaxes.empty()) {
      std::nth_element(parallaxes.begin(), parallaxes.begin() + parallaxes.size() / 2,
                       parallaxes.end());
      median = parallaxes[parallaxes.size() / 2];
    }
    std::printf(
        "rotation only        %zu frames posed by the rotation at the keyframe's position (parallax "
        "to the newest keyframe measured on %zu, median %.3f deg; below %.3f deg)\n",
        rotation_only_frames, parallax_frames, median, options.vo.rotation_only_parallax_deg);
  }
  std::printf("time per frame       mean %.1f ms  median %.1f ms  max %.1f ms (CPU, one core)\n",
              time.mean, time.median, time.max);
  const double per_frame = n ? 1.0 / n : 0.0;
  std::printf(
      "time per stage       features %.1f  matching %.1f  ICGM %.1f  geometry %.1f  mapping "
      "%.1f ms (CPU, mean per frame)\n",
      per_frame * stage_sum.features_ms, per_frame * stage_sum.matching_ms,
      per_frame * stage_sum.icgm_ms, per_frame * stage_sum.geometry_ms,
      per_frame * stage_sum.mapping_ms);
  if (source.groundtruth.empty()) {
    std::printf("ATE                  no ground truth\n");
    return 0;
  }
  icgm::MonoEvaluation eval;
  const icgm::Status s = icgm::EvaluateMonoTrajectory(source.groundtruth, estimate, 0.02, &eval);
  if (!s.ok()) {
    std::printf("ATE                  not computed: %s\n", s.reason().c_str());
    return 0;
  }
  std::printf("ATE (Sim(3))         rmse %.4f m  mean %.4f m  median %.4f m  (%zu poses)\n",
              eval.evaluation.ate.rmse, eval.evaluation.ate.mean, eval.evaluation.ate.median,
              eval.evaluation.num_associated());
  std::printf("distance travelled   %.2f m\n", eval.distance_m);
  {
    // The truth's spread about its centroid over the posed frames. The alignment's scale is
    // Horn's symmetric one (the spreads made equal), so the error is spread x sqrt(2 (1 - c)):
    // c = 1 for the truth's shape, 0 for a shape unrelated to it. Near the spread (c about
    // 0.5), the estimate carries little of the motion.
    const auto& truth = eval.evaluation.groundtruth;
    Eigen::Vector3d centroid = Eigen::Vector3d::Zero();
    for (const auto& p : truth) centroid += p.translation();
    centroid /= std::max<size_t>(1, truth.size());
    double sum_sq = 0.0;
    for (const auto& p : truth) sum_sq += (p.translation() - centroid).squaredNorm();
    const double spread = std::sqrt(sum_sq / std::max<size_t>(1, truth.size()));
    const double rmse = eval.evaluation.ate.rmse;
    std::printf("truth's spread       %.2f %% of distance (rmse %.4f m about its centroid over the "
                "posed frames); shape agreement c = 1 - (ATE / spread)^2 / 2 = %.3f\n",
                100.0 * spread / eval.distance_m, spread,
                spread > 0.0 ? 1.0 - 0.5 * (rmse / spread) * (rmse / spread) : 0.0);
  }
  std::printf("error of distance    %.2f %%\n", eval.error_percent);
  {
    icgm::MonoSegmentErrors segments;
    const icgm::Status ss =
        icgm::EvaluateMonoSegments(eval.evaluation, icgm::DefaultSegmentFractions(), &segments);
    if (ss.ok()) {
      std::printf("segment error        %.2f %% (mean over %zu segments; median %.2f %%; per length",
                  segments.mean_percent, segments.errors_percent.size(), segments.median_percent);
      for (const icgm::MonoSegmentLength& l : segments.lengths) {
        std::printf(" %.0f%%: %.2f", 100.0 * l.fraction, l.mean_percent);
      }
      std::printf("; standing still %.2f %%)\n", segments.standing_still_percent);
      std::printf("segment parts        rotation %.2f deg, direction of the displacement %.1f deg "
                  "(90: none), length estimate/true %.2f (median), length alone %.2f %%\n",
                  segments.rotation_error_deg, segments.direction_error_deg,
                  segments.length_ratio_median, segments.length_only_percent);
    } else {
      std::printf("segment error        not computed: %s\n", ss.reason().c_str());
    }
  }
  std::printf("Sim(3) scale         %.4f m per map unit\n", eval.scale);
  // Each map on its own (one Sim(3) each) and the run with the maps' scales made equal: how
  // much of the error the jumps between maps make.
  icgm::MonoMapBreakdown split;
  if (icgm::BreakDownMonoMaps(source.groundtruth, maps, 0.02, &split).ok()) {
    double sum_sq = 0.0, distance = 0.0;
    size_t poses = 0;
    for (const icgm::MonoMapFigures& m : split.maps) {
      if (!m.aligned) continue;
      sum_sq += m.poses * m.ate_rmse_m * m.ate_rmse_m;
      poses += m.poses;
      distance += m.distance_m;
    }
    std::printf(
        "ATE per map          rmse %.4f m over %zu of %zu maps (%zu poses), %.2f %% of "
        "%.2f m\n",
        std::sqrt(sum_sq / poses), split.aligned_maps, maps.size(), poses, split.per_map_percent,
        distance);
    std::printf("map scales          ");
    double previous = 0.0;
    for (const icgm::MonoMapFigures& m : split.maps) {
      if (!m.aligned) {
        std::printf(" (%zu poses)", m.poses);
        continue;
      }
      std::printf(" %.4f", m.scale);
      if (previous > 0.0) std::printf(" [x%.2f]", m.scale / previous);
      std::printf(" (%zu poses", m.poses);
      if (m.scale_first > 0.0 && m.scale_last > 0.0) {
        std::printf(", first %.4f last %.4f", m.scale_first, m.scale_last);
      }
      std::printf(")");
      previous = m.scale;
    }
    std::printf("\n");
    std::printf("scale jumps at resets");
    for (size_t k = 1; k < split.maps.size(); ++k) {
      const icgm::MonoMapFigures &a = split.maps[k - 1], &b = split.maps[k];
      if (a.scale_last > 0.0 && b.scale_first > 0.0) {
        std::printf(" x%.2f", b.scale_first / a.scale_last);
      } else {
        std::printf(" -");
      }
    }
    std::printf(" (local scale of a map's first poses over the last poses of the one before)\n");
    std::printf(
        "error split          whole %.2f %%, maps' scales made equal %.2f %%, scale carried "
        "exactly over resets %.2f %%, each map on its own %.2f %%\n",
        split.whole_percent, split.scale_fixed_percent, split.carry_fixed_percent,
        split.per_map_percent);
    // Each join on its own: what its re-initialization lost against the ground truth.
    for (const icgm::MonoJoinFigures& j : split.joins) {
      const icgm::Trajectory &before = maps[j.map - 1], &after = maps[j.map];
      const icgm::MonoFramesWithoutPose g =
          before.empty() || after.empty()
              ? icgm::MonoFramesWithoutPose()
              : gaps.CountsBetween(before.back().stamp,
                                   after.size() > 1 ? after[1].stamp : after.front().stamp);
      std::printf("join %zu               ", j.map);
      if (j.aligned) {
        std::printf("scale x%.2f, rotation %.1f deg, position %.3f m; ", j.scale_ratio,
                    j.rotation_deg, j.position_m);
      } else {
        std::printf("not aligned; ");
      }
      // The maps' own scales from the depth images, where the input has them.
      if (j.map < depth_scales.size() && !depth_scales[j.map - 1].empty() &&
          !depth_scales[j.map].empty()) {
        const double last_before =
            EdgeMedians(depth_scales[j.map - 1], icgm::MonoMapFigures::kEdgePoses).second;
        const double first_after =
            EdgeMedians(depth_scales[j.map], icgm::MonoMapFigures::kEdgePoses).first;
        std::printf("scale by depth x%.2f; ", first_after / last_before);
      }
      std::printf(
          "gap %.2f s (truth moved %.3f m, %.1f deg), %zu frames without pose (%zu lost then "
          "reset, %zu re-initializing)\n",
          j.gap_s, j.gap_motion_m, j.gap_rotation_deg, g.total(), g.lost_then_reset,
          g.reinitializing);
    }
    if (!split.joins.empty()) {
      std::printf(
          "joins made exact     %.2f %%, their rotation and position only %.2f %% (whole %.2f "
          "%%: the joins' share %.2f points, inside the maps %.2f %%)\n",
          split.joins_fixed_percent, split.joins_rigid_fixed_percent, split.whole_percent,
          split.whole_percent - split.joins_fixed_percent, split.per_map_percent);
    }
  }
  if (!depth_scales.empty()) {
    // The maps' own scale from the depth images, against the local Sim(3) scales above (which
    // also follow errors of the estimated motion).
    std::printf("map scales by depth ");
    for (const std::vector<double>& m : depth_scales) {
      if (m.empty()) {
        std::printf(" -");
        continue;
      }
      const auto [first, last] = EdgeMedians(m, icgm::MonoMapFigures::kEdgePoses);
      const auto [low, high] = std::minmax_element(m.begin(), m.end());
      std::printf(" (%zu frames, first %.4f last %.4f [x%.2f], range %.4f-%.4f)", m.size(), first,
                  last, last / first, *low, *high);
    }
    std::printf(" (metres per map unit: depth image over map depth of the tracked points)\n");
    icgm::MonoEvaluation metric;
    if (icgm::EvaluateMonoTrajectory(source.groundtruth, StepsInMetres(maps, pose_depth_scales),
                                     0.02, &metric)
            .ok()) {
      std::printf(
          "steps by depth scale %.2f %% of distance (each step in metres by its map's scale from "
          "the depth images: every map's scale held exactly, the motion's own errors kept)\n",
          metric.error_percent);
    }
  }
  if (r.segment_frames > 0) PrintSegments(source.groundtruth, estimate, stamps, r.segment_frames);
  if (!r.plot.empty()) {
    icgm::TrajectoryPlotOptions plot;
    plot.title = std::string("mono VO ") + (options.vo.use_icgm ? "with ICGM" : "without ICGM");
    const icgm::Status w =
        icgm::WriteTrajectoryPlot(r.plot, source.groundtruth, estimate, eval.evaluation, plot);
    if (!w.ok()) return icgm::tools::Failure(kTool, w.reason());
  }
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  Request r;
  try {
    const icgm::tools::CliArgs args(argc, argv,
                                    {"tum", "sim", "output", "plot", "log", "config", "camera",
                                     "max-frames", "sim-seed", "segment-frames", "bag",
                                     "rng-seed", "ransac-seed"},
                                    {"no-icgm", "no-wheels"});
    if (args.help()) return icgm::tools::PrintUsage(kTool);
    if (!args.positional().empty()) {
      return UsageError("unexpected argument '" + args.positional().front() + "'");
    }
    r.tum_dir = args.Get("tum");
    r.sim_path = args.Get("sim");
    r.bag_path = args.Get("bag");
    if (r.tum_dir.empty() + r.sim_path.empty() + r.bag_path.empty() != 2) {
      return UsageError("give exactly one of --tum, --sim, --bag");
    }
    r.output = args.Get("output");
    r.plot = args.Get("plot");
    r.log = args.Get("log");
    r.config = args.Get("config", r.config);
    r.camera = args.Get("camera", r.camera);
    r.no_icgm = args.Has("no-icgm");
    r.no_wheels = args.Has("no-wheels");
    r.max_frames = args.GetInt("max-frames", -1);
    if (args.Has("max-frames") && r.max_frames < 1)
      return UsageError("--max-frames must be positive");
    r.segment_frames = args.GetInt("segment-frames", 0);
    if (args.Has("segment-frames") && r.segment_frames < 10) {
      return UsageError("--segment-frames must be >= 10");
    }
    if (args.Has("sim-seed")) {
      if (r.sim_path.empty()) return UsageError("--sim-seed needs --sim");
      r.sim_seed = args.GetInt("sim-seed", 0);
      if (*r.sim_seed < 0) return UsageError("--sim-seed must be >= 0");
    }
    if (args.Has("rng-seed")) {
      r.rng_seed = args.GetInt("rng-seed", 0);
      if (*r.rng_seed < 0) return UsageError("--rng-seed must be >= 0");
    }
    if (args.Has("ransac-seed")) {
      r.ransac_seed = args.GetInt("ransac-seed", 0);
      if (*r.ransac_seed < 0) return UsageError("--ransac-seed must be >= 0");
    }
    r.camera_given = args.Has("camera");
    if (r.camera_given && r.tum_dir.empty() && r.bag_path.empty()) {
      return UsageError("--camera needs --tum or --bag");
    }
  } catch (const std::invalid_argument& e) {
    return UsageError(e.what());
  }
  try {
    return Run(r);
  } catch (const std::exception& e) {
    return icgm::tools::Failure(kTool, e.what());
  }
}
