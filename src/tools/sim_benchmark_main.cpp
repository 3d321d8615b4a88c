// icgm_sim_benchmark: renders a simulator scenario without writing a bag and prints the
// renderer's speed plus per-sequence figures (pedestrian coverage, valid depth). With --dump it
// also writes every n-th frame as PNGs (colour, false-colour depth, mask) for inspection.
// With --closed-loop it drives the closed-loop simulator instead (velocity commands following the
// scenario's route) and prints the cost of a Step and of a Render, and the collisions counted.
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <ctime>
#include <filesystem>
#include <string>

#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "core/common/progress_bar.h"
#include "core/common/status.h"
#include "core/sim/closed_loop_simulator.h"
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
    "                          [--dump DIR] [--dump-every N] [--closed-loop]\n"
    "  --closed-loop  step the closed-loop simulator along the route (velocity commands, frames\n"
    "                 1/frame_rate_hz apart) and time Step and Render separately";
constexpr icgm::tools::ToolInfo kTool{"icgm_sim_benchmark", kUsage};

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

// Parsed command line.
struct Request {
  std::string config;
  int seed = -1;    // < 0: the scenario's seed
  int frames = -1;  // < 0: the scenario's frame count
  std::string dump_dir;
  int dump_every = 30;
  bool closed_loop = false;
};

int UsageError(const std::string& message) { return icgm::tools::UsageError(kTool, message); }

// Drives the closed-loop simulator along its route for `frames` steps with a pure-pursuit
// follower (a point 1 m ahead on the route) at the route's cruise speed.
int RunClosedLoop(const icgm::sim::SimOptions& options, int frames) {
  using Clock = std::chrono::steady_clock;
  const auto t0 = Clock::now();
  icgm::sim::ClosedLoopSimulator sim(options);
  const double setup_s = std::chrono::duration<double>(Clock::now() - t0).count();
  const double dt = 1.0 / options.frame_rate_hz, speed = options.route.speed_mps;
  icgm::ProgressBar bar(frames, "step+render");
  double step_cpu_s = 0.0, render_cpu_s = 0.0, route_s_m = 0.0, coverage_sum = 0.0;
  for (int i = 0; i < frames; ++i) {
    const icgm::sim::PlanarPose& r = sim.planar_pose();
    const icgm::sim::PlanarPose target = sim.route().PoseAt(route_s_m + 1.0);
    const double bearing =
        std::remainder(std::atan2(target.y_m - r.y_m, target.x_m - r.x_m) - r.yaw_rad, 2 * M_PI);
    double cpu = ThreadCpuSeconds();
    sim.Step({speed, 2.0 * bearing}, dt);
    step_cpu_s += ThreadCpuSeconds() - cpu;
    route_s_m += sim.true_velocity().linear_mps * dt;
    cpu = ThreadCpuSeconds();
    const icgm::sim::SimFrame f = sim.Render();
    render_cpu_s += ThreadCpuSeconds() - cpu;
    coverage_sum += cv::countNonZero(f.dynamic_mask) / static_cast<double>(f.bgr.total());
    bar.Update(i + 1);
  }
  bar.Finish();
  std::printf("closed-loop steps    %d of %.3f s (%dx%d)\n", frames, dt, options.intrinsics.width_px,
              options.intrinsics.height_px);
  std::printf("setup                %.2f s (world, crowd)\n", setup_s);
  std::printf("step                 %.2f ms CPU (robot, odometry, %zu pedestrians, collisions)\n",
              1e3 * step_cpu_s / frames, sim.num_pedestrians());
  std::printf("render               %.1f ms CPU per frame, one thread\n",
              1e3 * render_cpu_s / frames);
  std::printf("step + render        %.1f ms CPU\n", 1e3 * (step_cpu_s + render_cpu_s) / frames);
  std::printf("mask coverage        mean %.1f%%\n", 100.0 * coverage_sum / frames);
  std::printf("driven               %.1f m in %.1f s\n", sim.distance_driven_m(), sim.elapsed_s());
  std::printf("collisions           static %d (min clearance %.2f m), pedestrians %d (min %.2f m)\n",
              sim.static_collisions().collisions, sim.static_collisions().min_clearance_m,
              sim.pedestrian_collisions().collisions, sim.pedestrian_collisions().min_clearance_m);
  return 0;
}

int Run(const Request& request) {
  icgm::sim::SimOptions options = icgm::sim::LoadSimOptions(request.config);
  if (request.seed >= 0) options.seed = request.seed;
  if (request.closed_loop) {
    return RunClosedLoop(options, request.frames > 0 ? request.frames : options.num_frames);
  }
  if (request.frames > 0) {
    options.num_frames = request.frames;
    options.route.laps = 0.0;
  }
  const std::string& dump_dir = request.dump_dir;
  const int dump_every = request.dump_every;
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
  Request request;
  try {
    const icgm::tools::CliArgs args(argc, argv, {"config", "frames", "seed", "dump", "dump-every"},
                                    {"closed-loop"});
    if (args.help()) return icgm::tools::PrintUsage(kTool);
    if (!args.positional().empty()) {
      return UsageError("unexpected argument '" + args.positional().front() + "'");
    }
    request.config = args.Require("config");
    request.seed = args.GetInt("seed", -1);
    request.frames = args.GetInt("frames", -1);
    request.dump_dir = args.Get("dump");
    request.dump_every = args.GetInt("dump-every", request.dump_every);
    request.closed_loop = args.Has("closed-loop");
    if (args.Has("seed") && request.seed < 0) return UsageError("--seed must be >= 0");
    if (args.Has("frames") && request.frames < 1) return UsageError("--frames must be positive");
    if (request.dump_every < 1) return UsageError("--dump-every must be positive");
    if (request.closed_loop && !request.dump_dir.empty()) {
      return UsageError("--dump is not available with --closed-loop");
    }
  } catch (const std::invalid_argument& e) {
    return UsageError(e.what());
  }
  try {
    return Run(request);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "icgm_sim_benchmark: %s\n", e.what());
    return 1;
  }
}
