#include "tools/offline_sources.h"

#include <cstdio>
#include <stdexcept>

#include "core/dataset/tum_dataset.h"
#include "core/sim/frame_prefetcher.h"
#include "core/sim/sim_export.h"
#include "core/sim/sim_options.h"
#include "core/sim/simulator.h"

#ifdef ICGM_WITH_ROS_BRIDGE
#include "ros_bridge/bag_reader.h"
#endif

namespace icgm::tools {

OfflineSource OpenTumSource(const std::string& dir, const CameraIntrinsics& intrinsics,
                            const std::string& tool) {
  auto dataset = std::make_shared<TumDataset>(TumDataset::Open(dir, intrinsics));
  OfflineSource source;
  source.intrinsics = dataset->intrinsics();
  source.groundtruth = dataset->groundtruth();
  source.expected_frames = dataset->size();
  auto skipped = source.skipped_frames;
  // An unreadable or wrongly sized image skips its frame rather than ending the run early.
  source.frames = TumFrameSource(dataset, [skipped, tool](size_t i, const std::string& why) {
    ++*skipped;
    std::fprintf(stderr, "\n%s: warning: frame %zu skipped: %s\n", tool.c_str(), i, why.c_str());
  });
  return source;
}

OfflineSource OpenBagSource(const std::string& path,
                            const std::optional<CameraIntrinsics>& fallback) {
#ifdef ICGM_WITH_ROS_BRIDGE
  auto reader = std::make_shared<ros_bridge::BagReader>(path);
  ros_bridge::RgbdBagTopics topics;
  topics.fallback_intrinsics = fallback;
  std::shared_ptr<ros_bridge::RgbdBagStream> stream;
  try {
    stream = std::make_shared<ros_bridge::RgbdBagStream>(*reader, topics);
  } catch (const LoadError& e) {
    const std::string what = e.what();
    if (fallback || what.find("camera_info") == std::string::npos) throw;
    throw LoadError(what + " (--camera FILE)");
  }
  OfflineSource source;
  source.intrinsics = stream->intrinsics();
  source.groundtruth = stream->ground_truth();
  source.wheel_odometry = stream->wheel_odometry();
  source.base_to_camera = stream->base_to_camera();
  source.expected_frames = stream->expected_frames();
  source.frames = [reader, stream](SlamInputFrame* f, std::string* error) {
    ros_bridge::RgbdBagFrame frame;
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
  return source;
#else
  (void)fallback;
  throw std::invalid_argument("--bag " + path +
                              ": this build has no ROS bridge (build the catkin package)");
#endif
}

OfflineSource OpenSimSource(const std::string& scenario_path, std::optional<int> seed) {
  sim::SimOptions sim_options = sim::LoadSimOptions(scenario_path);
  if (seed) sim_options.seed = *seed;
  auto simulator = std::make_shared<sim::Simulator>(sim_options);
  OfflineSource source;
  source.intrinsics = simulator->intrinsics();
  source.groundtruth = sim::CameraGroundTruth(*simulator);
  source.wheel_odometry = sim::WheelOdometryTrajectory(*simulator);
  source.base_to_camera = simulator->base_to_camera();  // none for a handheld camera
  source.expected_frames = simulator->size();
  auto prefetcher = std::make_shared<sim::FramePrefetcher>(*simulator);
  // The prefetcher refers to the simulator: capture both, simulator first to outlive it.
  source.frames = [simulator, prefetcher](SlamInputFrame* f, std::string*) {
    sim::SimFrame frame;
    if (!prefetcher->Next(&frame)) return false;
    f->stamp = frame.stamp;
    f->depth_stamp.reset();
    f->bgr = frame.bgr;
    f->depth_m = frame.depth_m;
    f->dynamic_mask = frame.dynamic_mask;
    return true;
  };
  return source;
}

}  // namespace icgm::tools
