// icgm_sim: renders a simulator scenario into a rosbag with the robot's sensor topics and
// evaluation-only ground truth, plus the ground-truth camera trajectory (<name>.gt.txt) and the
// wheel odometry (<name>.odom.txt) in TUM format next to the bag.
#include <cstdio>
#include <exception>
#include <filesystem>
#include <optional>
#include <string>

#include "core/common/progress_bar.h"
#include "core/common/status.h"
#include "core/dataset/trajectory.h"
#include "core/sim/frame_prefetcher.h"
#include "core/sim/sim_export.h"
#include "core/sim/simulator.h"
#include "ros_bridge/bag_writer.h"
#include "ros_bridge/topics.h"
#include "tools/cli_args.h"

namespace {

namespace topics = icgm::ros_bridge::topics;

constexpr char kUsage[] =
    "usage: icgm_sim --config config/sim/<scenario>.yaml --out rosbags/<name>.bag\n"
    "                [--seed N] [--frames N] [--depth 16UC1|32FC1] [--no-mask]\n"
    "  Writes the bag plus <name>.gt.txt (camera in world) and <name>.odom.txt (base_link in\n"
    "  odom). Depth: 16UC1 millimetres on /camera/depth_registered/image_raw (default) or\n"
    "  32FC1 metres on /camera/depth_registered/image.\n";
constexpr icgm::tools::ToolInfo kTool{"icgm_sim", kUsage};

int UsageError(const std::string& message) { return icgm::tools::UsageError(kTool, message); }

void WriteFrame(const icgm::sim::Simulator& sim, const icgm::sim::SimFrame& f, bool depth_mm,
                bool with_mask, icgm::ros_bridge::BagWriter* bag) {
  const icgm::CameraIntrinsics& K = sim.intrinsics();
  bag->WriteImage(topics::kRgbImage, topics::kCameraFrame, f.stamp, f.bgr, "bgr8");
  // The mask goes before the depth image: readers pair a frame once colour and depth are in.
  if (with_mask) {
    bag->WriteImage(topics::kDynamicMask, topics::kCameraFrame, f.stamp, f.dynamic_mask, "mono8");
  }
  bag->WriteCameraInfo(topics::kRgbInfo, topics::kCameraFrame, f.stamp, K);
  if (depth_mm) {
    bag->WriteImage(topics::kDepthImageMm, topics::kCameraFrame, f.stamp,
                    icgm::sim::DepthToMillimetres(f.depth_m), "16UC1");
  } else {
    bag->WriteImage(topics::kDepthImageM, topics::kCameraFrame, f.stamp, f.depth_m, "32FC1");
  }
  bag->WriteCameraInfo(topics::kDepthInfo, topics::kCameraFrame, f.stamp, K);
  // A hand-held camera has no wheels and no base link: the bag claims none.
  if (sim.has_wheel_odometry()) {
    bag->WriteOdometry(topics::kWheelOdom, f.stamp, topics::kOdomFrame, topics::kBaseFrame,
                       f.odometry.T_odom_base, f.odometry.linear_velocity_mps,
                       f.odometry.angular_velocity_rps);
    bag->WriteTransform(f.stamp, topics::kOdomFrame, topics::kBaseFrame, f.odometry.T_odom_base,
                        false);
  }
  bag->WritePose(topics::kGroundTruthPose, f.stamp, topics::kWorldFrame, f.T_world_camera);
}

}  // namespace

int main(int argc, char** argv) {
  std::string config_path, out_path, depth_format;
  int seed = -1, frames = -1;
  bool with_mask = true;
  try {
    const icgm::tools::CliArgs args(argc, argv, {"config", "out", "seed", "frames", "depth"},
                                    {"no-mask"});
    if (args.help()) return icgm::tools::PrintUsage(kTool);
    if (!args.positional().empty()) {
      return UsageError("unexpected argument '" + args.positional().front() + "'");
    }
    config_path = args.Require("config");
    out_path = args.Require("out");
    seed = args.GetInt("seed", -1);
    frames = args.GetInt("frames", -1);
    depth_format = args.Get("depth", "16UC1");
    with_mask = !args.Has("no-mask");
    if (args.Has("seed") && seed < 0) return UsageError("--seed must be >= 0");
    if (args.Has("frames") && frames < 1) return UsageError("--frames must be positive");
    if (depth_format != "16UC1" && depth_format != "32FC1") {
      return UsageError("--depth must be 16UC1 or 32FC1, not '" + depth_format + "'");
    }
  } catch (const std::invalid_argument& e) {
    return UsageError(e.what());
  }

  try {
    icgm::sim::SimOptions options = icgm::sim::LoadSimOptions(config_path);
    if (seed >= 0) options.seed = seed;
    if (frames > 0) {
      options.num_frames = frames;
      options.route.laps = 0.0;  // an explicit frame count overrides the lap count
    }
    const std::filesystem::path parent = std::filesystem::path(out_path).parent_path();
    if (!parent.empty()) std::filesystem::create_directories(parent);

    const icgm::sim::Simulator sim(options);
    icgm::ros_bridge::BagWriter bag(out_path);
    if (const std::optional<icgm::Pose3> extrinsic = sim.base_to_camera()) {
      bag.WriteTransform(sim.stamp(0), topics::kBaseFrame, topics::kCameraFrame, *extrinsic, true);
    }
    icgm::ProgressBar bar(sim.size(), "icgm_sim");
    // Rendering runs one frame ahead on a worker thread while this thread writes.
    icgm::sim::FramePrefetcher frames(sim);
    icgm::sim::SimFrame frame;
    while (frames.Next(&frame)) {
      WriteFrame(sim, frame, depth_format == "16UC1", with_mask, &bag);
      bar.Update(frame.index + 1);
    }
    bar.Finish();
    bag.Close();

    const std::string gt_path = icgm::sim::SidecarPath(out_path, ".gt.txt");
    const std::string odom_path = icgm::sim::SidecarPath(out_path, ".odom.txt");
    icgm::WriteTumTrajectory(gt_path, icgm::sim::CameraGroundTruth(sim));
    if (sim.has_wheel_odometry()) {
      icgm::WriteTumTrajectory(odom_path, icgm::sim::WheelOdometryTrajectory(sim));
    }
    std::printf("wrote %s (%zu frames, %.1f s, %zu pedestrians, seed %d)\n", out_path.c_str(),
                sim.size(), icgm::DurationSeconds(sim.stamp(sim.size() - 1), sim.stamp(0)),
                sim.crowd().num_pedestrians(), options.seed);
    std::printf("wrote %s\n", gt_path.c_str());
    if (sim.has_wheel_odometry()) std::printf("wrote %s\n", odom_path.c_str());
    return 0;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "icgm_sim: %s\n", e.what());
    return 1;
  }
}
