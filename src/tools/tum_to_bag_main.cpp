// icgm_tum_to_bag: converts a TUM RGB-D benchmark folder into a rosbag with the project's topic
// conventions: colour, registered depth, camera info and the ground truth as
// /ground_truth/pose (camera in "world"), so real sequences replay like simulated ones.
#include <algorithm>
#include <cstdio>
#include <exception>
#include <filesystem>
#include <string>

#include "core/common/progress_bar.h"
#include "core/common/status.h"
#include "core/dataset/camera_options.h"
#include "core/dataset/tum_dataset.h"
#include "core/sim/sim_export.h"
#include "ros_bridge/bag_writer.h"
#include "ros_bridge/topics.h"
#include "tools/cli_args.h"

namespace {

namespace topics = icgm::ros_bridge::topics;

constexpr char kUsage[] =
    "usage: icgm_tum_to_bag DIR --out FILE.bag [--camera config/camera/tum_fr1.yaml]\n"
    "                       [--depth 16UC1|32FC1] [--max-dt 0.02] [--frames N]\n"
    "  DIR holds rgb.txt, depth.txt and optionally groundtruth.txt. Depth is written as 16UC1\n"
    "  millimetres on /camera/depth_registered/image_raw (default) or 32FC1 metres on\n"
    "  /camera/depth_registered/image.\n";
constexpr icgm::tools::ToolInfo kTool{"icgm_tum_to_bag", kUsage};

int UsageError(const std::string& message) { return icgm::tools::UsageError(kTool, message); }

}  // namespace

int main(int argc, char** argv) {
  std::string dir, out_path, camera_path, depth_format;
  double max_dt_s = 0.02;
  int max_frames = -1;
  try {
    const icgm::tools::CliArgs args(argc, argv, {"out", "camera", "depth", "max-dt", "frames"},
                                    {});
    if (args.help()) return icgm::tools::PrintUsage(kTool);
    if (args.positional().size() != 1) return UsageError("expected exactly one dataset folder");
    dir = args.positional().front();
    out_path = args.Require("out");
    camera_path = args.Get("camera", "config/camera/tum_fr1.yaml");
    depth_format = args.Get("depth", "16UC1");
    max_dt_s = args.GetDouble("max-dt", max_dt_s);
    max_frames = args.GetInt("frames", -1);
    if (depth_format != "16UC1" && depth_format != "32FC1") {
      return UsageError("--depth must be 16UC1 or 32FC1, not '" + depth_format + "'");
    }
    if (!(max_dt_s >= 0.0)) return UsageError("--max-dt must be >= 0");
    if (args.Has("frames") && max_frames < 1) return UsageError("--frames must be positive");
  } catch (const std::invalid_argument& e) {
    return UsageError(e.what());
  }

  try {
    const icgm::CameraIntrinsics intrinsics = icgm::LoadCameraIntrinsics(camera_path);
    const icgm::TumDataset data = icgm::TumDataset::Open(dir, intrinsics, max_dt_s);
    if (data.size() == 0) throw icgm::LoadError("no colour/depth pairs in '" + dir + "'");
    const size_t n =
        max_frames > 0 ? std::min(data.size(), static_cast<size_t>(max_frames)) : data.size();
    const std::filesystem::path parent = std::filesystem::path(out_path).parent_path();
    if (!parent.empty()) std::filesystem::create_directories(parent);

    icgm::ros_bridge::BagWriter bag(out_path);
    const bool depth_mm = depth_format == "16UC1";
    icgm::ProgressBar bar(n, "icgm_tum_to_bag");
    for (size_t i = 0; i < n; ++i) {
      const icgm::RgbdFrameRef& f = data.frame(i);
      bag.WriteImage(topics::kRgbImage, topics::kCameraFrame, f.stamp, data.LoadBgr(i), "bgr8");
      bag.WriteCameraInfo(topics::kRgbInfo, topics::kCameraFrame, f.stamp, intrinsics);
      const cv::Mat depth_m = data.LoadDepthM(i);
      if (depth_mm) {
        bag.WriteImage(topics::kDepthImageMm, topics::kCameraFrame, f.depth_stamp,
                       icgm::sim::DepthToMillimetres(depth_m), "16UC1");
      } else {
        bag.WriteImage(topics::kDepthImageM, topics::kCameraFrame, f.depth_stamp, depth_m, "32FC1");
      }
      bag.WriteCameraInfo(topics::kDepthInfo, topics::kCameraFrame, f.depth_stamp, intrinsics);
      bar.Update(i + 1);
    }
    bar.Finish();
    // Ground truth over the converted frames' time span (with 1 s margin for interpolation).
    size_t gt_written = 0;
    const double first_s = data.frame(0).stamp.seconds() - 1.0;
    const double last_s = data.frame(n - 1).stamp.seconds() + 1.0;
    for (const icgm::StampedPose& p : data.groundtruth()) {
      if (p.stamp.seconds() < first_s || p.stamp.seconds() > last_s) continue;
      bag.WritePose(topics::kGroundTruthPose, p.stamp, topics::kWorldFrame, p.pose);
      ++gt_written;
    }
    bag.Close();
    std::printf("wrote %s (%zu frames, %zu ground-truth poses, depth %s)\n", out_path.c_str(), n,
                gt_written, depth_format.c_str());
    return 0;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "icgm_tum_to_bag: %s\n", e.what());
    return 1;
  }
}
