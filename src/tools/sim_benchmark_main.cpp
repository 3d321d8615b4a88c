// icgm_sim_benchmark: renders a simulator scenario without writing a bag and prints the
// renderer's speed plus per-sequence figures (pedestrian coverage, valid depth). With --dump it
// also writes every n-th frame as PNGs (colour, false-colour depth, mask) for inspection.
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <ctime>
#include <filesystem>
#include <iostream>

#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "core/common/progress_bar.h"
#include "core/common/status.h"
#include "core/sim/simulator.h"
#include "tools/cli_args.h"

namespace {

// CPU time of the calling thread: the renderer's cost independent of other load on the machine.
double ThreadCpuSeconds() {
  timespec ts{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
  return ts.tv_sec + 1e-9 * ts.tv_nsec;
}

constexpr char kUsage[] =
    "usage: icgm_sim_benchmark --config config/sim/<scenario>.yaml [--frames N] [--seed N]\n"
    "                          [--dump DIR] [--dump-every N]";

void DumpFrame(const std::string& dir, const icgm::sim::SimFrame& f) {
  char name[32];
  std::snprintf(name, sizeof(name), "%05zu", f.index);
  const std::string base = dir + "/" + name;
  cv::imwrite(base + "_rgb.png", f.bgr);
  // Depth in false colour (blue near, red at 6 m), invalid pixels black.
  const cv::Mat invalid = ~(f.depth_m == f.depth_m);
  cv::Mat depth8;
  f.depth_m.convertTo(depth8, CV_8UC1, 255.0 / 6.0);
  cv::Mat depth_color;
  cv::applyColorMap(depth8, depth_color, cv::COLORMAP_JET);
  depth_color.setTo(cv::Scalar(0, 0, 0), invalid);
  cv::imwrite(base + "_depth.png", depth_color);
  cv::imwrite(base + "_mask.png", f.dynamic_mask);
}

int Run(const icgm::tools::CliArgs& args) {
  icgm::sim::SimOptions options = icgm::sim::LoadSimOptions(args.Require("config"));
  if (args.Has("seed")) options.seed = args.GetInt("seed", options.seed);
  if (args.Has("frames")) {
    options.num_frames = args.GetInt("frames", options.num_frames);
    options.route.laps = 0.0;
  }
  if (options.num_frames < 1) throw std::invalid_argument("--frames must be positive");
  const std::string dump_dir = args.Get("dump");
  const int dump_every = args.GetInt("dump-every", 30);
  if (dump_every < 1) throw std::invalid_argument("--dump-every must be positive");
  if (!dump_dir.empty()) std::filesystem::create_directories(dump_dir);

  using Clock = std::chrono::steady_clock;
  const auto t0 = Clock::now();
  const icgm::sim::Simulator sim(options);
  const double setup_s = std::chrono::duration<double>(Clock::now() - t0).count();

  icgm::ProgressBar bar(sim.size(), "render");
  double render_cpu_s = 0.0, render_s = 0.0, coverage_sum = 0.0, coverage_max = 0.0,
         valid_sum = 0.0;
  for (size_t i = 0; i < sim.size(); ++i) {
    const auto t = Clock::now();
    const double cpu = ThreadCpuSeconds();
    const icgm::sim::SimFrame f = sim.Render(i);
    render_cpu_s += ThreadCpuSeconds() - cpu;
    render_s += std::chrono::duration<double>(Clock::now() - t).count();
    const double pixels = static_cast<double>(f.bgr.total());
    const double coverage = cv::countNonZero(f.dynamic_mask) / pixels;
    coverage_sum += coverage;
    coverage_max = std::max(coverage_max, coverage);
    valid_sum += cv::countNonZero(f.depth_m == f.depth_m) / pixels;
    if (!dump_dir.empty() && i % dump_every == 0) DumpFrame(dump_dir, f);
    bar.Update(i + 1);
  }
  bar.Finish();
  const double n = static_cast<double>(sim.size());
  std::printf("frames               %zu (%dx%d)\n", sim.size(), options.intrinsics.width_px,
              options.intrinsics.height_px);
  std::printf("setup                %.2f s (world, crowd, odometry)\n", setup_s);
  std::printf("render               %.1f frames/s of CPU time (%.1f ms/frame, one thread)\n",
              n / render_cpu_s, 1e3 * render_cpu_s / n);
  std::printf("render wall clock    %.1f frames/s (includes waiting for a busy CPU)\n",
              n / render_s);
  std::printf("pedestrians          %zu\n", sim.crowd().num_pedestrians());
  std::printf("mask coverage        mean %.1f%%  max %.1f%%\n", 100.0 * coverage_sum / n,
              100.0 * coverage_max);
  std::printf("valid depth          mean %.1f%%\n", 100.0 * valid_sum / n);
  std::printf("sequence             %.1f s, route loop %.1f m\n",
              icgm::DurationSeconds(sim.stamp(sim.size() - 1), sim.stamp(0)),
              sim.route().length_m());
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  try {
    const icgm::tools::CliArgs args(argc, argv, {"config", "frames", "seed", "dump", "dump-every"},
                                    {});
    if (!args.positional().empty())
      throw std::invalid_argument("unexpected argument '" + args.positional().front() + "'");
    args.Require("config");
    try {
      return Run(args);
    } catch (const std::invalid_argument& e) {
      throw;
    } catch (const std::exception& e) {
      std::cerr << "icgm_sim_benchmark: " << e.what() << "\n";
      return 1;
    }
  } catch (const std::invalid_argument& e) {
    std::cerr << "icgm_sim_benchmark: " << e.what() << "\n" << kUsage << "\n";
    return 2;
  }
}
