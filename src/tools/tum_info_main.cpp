// icgm_tum_info: what a TUM RGB-D sequence folder holds after association: frame count, colour
// images left without depth, association offsets, duration and rate, ground-truth coverage,
// and (with --check-images) whether every image loads with the expected size and how much of
// the depth is valid.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <exception>
#include <string>
#include <vector>

#include "core/common/progress_bar.h"
#include "core/common/status.h"
#include "core/dataset/camera_options.h"
#include "core/dataset/depth_image.h"
#include "core/dataset/tum_dataset.h"
#include "core/eval/error_stats.h"
#include "tools/cli_args.h"

namespace {

constexpr char kUsage[] =
    "usage: icgm_tum_info --tum DIR [--camera camera.yaml] [--max-dt 0.02] [--check-images]\n"
    "  Summarizes a TUM RGB-D folder (rgb.txt, depth.txt, groundtruth.txt). --camera defaults\n"
    "  to the TUM fr1 calibration; --check-images loads every frame.\n";
constexpr icgm::tools::ToolInfo kTool{"icgm_tum_info", kUsage};

int UsageError(const std::string& message) { return icgm::tools::UsageError(kTool, message); }

}  // namespace

int main(int argc, char** argv) {
  std::string dir, camera_path;
  double max_dt_s = 0.02;
  bool check_images = false;
  try {
    const icgm::tools::CliArgs args(argc, argv, {"tum", "camera", "max-dt"},
                                    {"check-images"});
    if (args.help()) return icgm::tools::PrintUsage(kTool);
    if (!args.positional().empty()) {
      return UsageError("unexpected argument '" + args.positional().front() + "'");
    }
    dir = args.Require("tum");
    camera_path = args.Get("camera");
    max_dt_s = args.GetDouble("max-dt", max_dt_s);
    check_images = args.Has("check-images");
    if (!(max_dt_s >= 0.0) || !std::isfinite(max_dt_s)) {
      return UsageError("--max-dt must be a finite value >= 0");
    }
  } catch (const std::invalid_argument& e) {
    return UsageError(e.what());
  }

  try {
    icgm::CameraIntrinsics intrinsics;
    if (camera_path.empty()) {
      intrinsics.fx_px = 517.3;
      intrinsics.fy_px = 516.5;
      intrinsics.cx_px = 318.6;
      intrinsics.cy_px = 255.3;
      intrinsics.depth_scale = 5000.0;
    } else {
      intrinsics = icgm::LoadCameraIntrinsics(camera_path);
    }
    const icgm::TumDataset ds = icgm::TumDataset::Open(dir, intrinsics, max_dt_s);
    std::printf("folder           %s\n", dir.c_str());
    std::printf(
        "frames           %zu associated (max dt %.3f s), %zu colour images without depth\n",
        ds.size(), max_dt_s, ds.unmatched_rgb());
    if (ds.size() == 0) return 0;
    std::vector<double> offsets_ms;
    for (size_t i = 0; i < ds.size(); ++i) {
      offsets_ms.push_back(
          1e3 * std::abs(icgm::DurationSeconds(ds.frame(i).depth_stamp, ds.frame(i).stamp)));
    }
    const icgm::ErrorStats off = icgm::ComputeErrorStats(offsets_ms);
    std::printf("|rgb - depth|    mean %.2f ms, median %.2f ms, max %.2f ms\n", off.mean,
                off.median, off.max);
    const double duration_s =
        icgm::DurationSeconds(ds.frame(ds.size() - 1).stamp, ds.frame(0).stamp);
    std::printf("duration         %.2f s (%.1f frames/s)\n", duration_s,
                duration_s > 0 ? (ds.size() - 1) / duration_s : 0.0);
    if (ds.has_groundtruth()) {
      size_t covered = 0;
      for (size_t i = 0; i < ds.size(); ++i) {
        covered += icgm::PoseAt(ds.groundtruth(), ds.frame(i).stamp).has_value() ? 1 : 0;
      }
      std::printf("ground truth     %zu poses, %zu of %zu frames covered (gap <= 0.1 s)\n",
                  ds.groundtruth().size(), covered, ds.size());
    } else {
      std::printf("ground truth     none\n");
    }
    if (check_images) {
      icgm::ProgressBar bar(ds.size(), "loading");
      std::vector<double> valid_fraction;
      for (size_t i = 0; i < ds.size(); ++i) {
        ds.LoadBgr(i);
        const cv::Mat depth = ds.LoadDepthM(i);
        valid_fraction.push_back(static_cast<double>(icgm::CountValidDepth(depth)) /
                                 static_cast<double>(depth.total()));
        bar.Update(i + 1);
      }
      bar.Finish();
      const icgm::ErrorStats v = icgm::ComputeErrorStats(valid_fraction);
      std::printf("images           all %zu pairs load at %dx%d\n", ds.size(), intrinsics.width_px,
                  intrinsics.height_px);
      std::printf("valid depth      mean %.1f%%, min %.1f%% of pixels\n", 100.0 * v.mean,
                  100.0 * v.min);
    }
  } catch (const icgm::LoadError& e) {
    std::fprintf(stderr, "icgm_tum_info: %s\n", e.what());
    return 1;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "icgm_tum_info: unexpected error: %s\n", e.what());
    return 1;
  }
  return 0;
}
