// Runs a SlamSystem over any frame source (a TUM RGB-D folder here; a rosbag in the ROS tools)
// and gathers what the offline tools report: per-stage timing, keyframes, loop closures and the
// map's memory. Wheel odometry samples are fed up to wheel_lead_s after each frame stamp, as a
// live system would have received them.
#pragma once

#include <cstddef>
#include <functional>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <opencv2/core.hpp>

#include "core/common/time.h"
#include "core/dataset/trajectory.h"
#include "core/dataset/tum_dataset.h"
#include "core/map/hybrid_map.h"
#include "core/slam/slam_system.h"

namespace icgm {

struct SlamInputFrame {
  Time stamp;
  cv::Mat bgr;      // CV_8UC3 BGR (or gray)
  cv::Mat depth_m;  // CV_32FC1 metres, NaN/0 invalid
  std::optional<Time> depth_stamp;  // when the depth image was stamped (default: stamp)
  // Ground truth for evaluation only (the simulator, simulated bags): non-zero on pedestrians;
  // empty when the source has none. Never given to the system.
  cv::Mat dynamic_mask;
};

// Fills *frame and returns true, or returns false at the end of the input (setting *error when
// the input failed rather than ended).
using SlamFrameSource = std::function<bool(SlamInputFrame* frame, std::string* error)>;

// Frames of a TUM RGB-D folder in stamp order. A frame whose images cannot be read ends the
// input with an error; with `on_skip`, it is skipped instead and reported to on_skip (frame
// index, reason), and the run goes on.
using SkippedFrameFn = std::function<void(size_t index, const std::string& reason)>;
SlamFrameSource TumFrameSource(std::shared_ptr<const TumDataset> dataset,
                               SkippedFrameFn on_skip = SkippedFrameFn());

// The options in <config_dir> (LoadSlamOptions) and the TUM folder `tum_dir` read with the
// camera intrinsics of `camera_path`: what the TUM-based tools start from. Throws LoadError.
struct TumSlamInput {
  SlamOptions options;
  std::shared_ptr<TumDataset> dataset;
};
TumSlamInput LoadTumSlamInput(const std::string& config_dir, const std::string& tum_dir,
                              const std::string& camera_path);

struct SlamRunOptions {
  size_t max_frames = 0;      // 0: the whole input
  Trajectory wheel_odometry;  // T_odom_base samples in time order (may be empty)
  double wheel_lead_s = 0.05;
  // Called after every frame (progress bars, live output, evaluation against the input's
  // ground truth).
  std::function<void(size_t frames_done, const SlamInputFrame& input, const SlamFrameResult&)>
      on_frame;
};

// Milliseconds per frame (front-end stages) or per keyframe (map stages).
struct SlamStageTimes {
  std::vector<double> features, matching, icgm, registration, fusion, frontend_total;
  std::vector<double> map_update;         // per keyframe: MapBuilder::AddKeyframe
  std::vector<double> loop_registration;  // per keyframe: the RegisterFn calls in it
  std::vector<double> frame_total;        // per frame: front end + map
  // per frame: CPU time of the calling thread in SlamSystem::ProcessFrame (with
  // cv::setNumThreads(1), the cost on one core whatever else the machine does)
  std::vector<double> thread_cpu;
};

struct SlamRunReport {
  size_t frames = 0;
  size_t keyframes = 0;      // front-end keyframes
  size_t map_keyframes = 0;  // taken by the map
  size_t loop_queries = 0;   // keyframes for which loop closure registered candidates
  size_t loop_registrations = 0;
  size_t loop_closures = 0;
  std::map<std::string, size_t> input_problems;  // front-end input status reasons
  std::map<std::string, size_t> map_problems;    // keyframes the map refused
  std::string input_error;                       // the source failed (not just ended)
  SlamStageTimes times;
};

// Runs until the source ends or max_frames. Never throws.
SlamRunReport RunSlam(SlamSystem* system, const SlamFrameSource& source,
                      const SlamRunOptions& options);

// Bytes of the metric models' payload (keypoints, descriptors, 3-D points, poses) and links.
size_t MapPayloadBytes(const HybridMap& map);

// Human-readable summary: frames, keyframes, loop closures, stage timing (mean, median, p95),
// map memory per keyframe.
std::string FormatSlamReport(const SlamRunReport& report, const SlamSystem& system);

}  // namespace icgm
