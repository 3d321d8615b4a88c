#include "core/slam/slam_runner.h"

#include "core/common/sample_summary.h"
#include "core/common/thread_cpu_time.h"
#include "core/dataset/camera_options.h"
#include "core/slam/wheel_feed.h"

#include <time.h>

#include <algorithm>
#include <cstdio>
#include <exception>
#include <utility>

namespace icgm {

SlamFrameSource TumFrameSource(std::shared_ptr<const TumDataset> dataset,
                               SkippedFrameFn on_skip) {
  auto next = std::make_shared<size_t>(0);
  return [dataset, next, on_skip](SlamInputFrame* frame, std::string* error) {
    while (*next < dataset->size()) {
      const size_t i = (*next)++;
      try {
        frame->stamp = dataset->frame(i).stamp;
        frame->bgr = dataset->LoadBgr(i);
        frame->depth_m = dataset->LoadDepthM(i);
        frame->depth_stamp = dataset->frame(i).depth_stamp;
        frame->dynamic_mask = cv::Mat();
        return true;
      } catch (const LoadError& e) {
        if (!on_skip) {
          *error = e.what();
          return false;
        }
        on_skip(i, e.what());
      }
    }
    return false;
  };
}

namespace {

std::string Head(const std::string& reason) { return reason.substr(0, reason.find(':')); }

void Record(const SlamFrameResult& r, SlamRunReport* report) {
  const FrontendFrameResult& f = r.frontend;
  if (!f.status.ok()) ++report->input_problems[Head(f.status.reason())];
  SlamStageTimes& t = report->times;
  if (f.frame_index > 0) {
    t.features.push_back(f.times.undistort_ms + f.times.features_ms);
    t.matching.push_back(f.times.matching_ms);
    t.icgm.push_back(f.times.icgm_ms);
    t.registration.push_back(f.times.registration_ms);
    t.fusion.push_back(f.times.fusion_ms);
    t.frontend_total.push_back(f.times.total_ms);
  }
  t.frame_total.push_back(f.times.total_ms + r.map_ms);
  if (!r.keyframe) return;
  ++report->keyframes;
  if (r.keyframe_id >= 0) ++report->map_keyframes;
  if (!r.map_status.ok()) ++report->map_problems[Head(r.map_status.reason())];
  t.map_update.push_back(r.map_ms);
  t.loop_registration.push_back(r.loop_registration_ms);
  if (r.loop_registrations > 0) ++report->loop_queries;
  report->loop_registrations += static_cast<size_t>(r.loop_registrations);
  if (r.update.loop_closed) ++report->loop_closures;
}

using Summary = SampleSummary;

}  // namespace

SlamRunReport RunSlam(SlamSystem* system, const SlamFrameSource& source,
                      const SlamRunOptions& options) {
  SlamRunReport report;
  WheelFeed wheel(options.wheel_lead_s, options.wheel_odometry.size() + 1);
  for (const StampedPose& w : options.wheel_odometry) wheel.Add(w.stamp, w.pose);
  SlamInputFrame frame;
  try {
    while (options.max_frames == 0 || report.frames < options.max_frames) {
      if (!source(&frame, &report.input_error)) break;
      wheel.FeedUpTo(frame.stamp, [system](Time t, const Pose3& odom_base) {
        system->AddWheelOdometry(t, odom_base);
      });
      const double cpu0 = ThreadCpuMs();
      const SlamFrameResult r =
          system->ProcessFrame(frame.stamp, frame.bgr, frame.depth_m, frame.depth_stamp);
      report.times.thread_cpu.push_back(ThreadCpuMs() - cpu0);
      ++report.frames;
      Record(r, &report);
      if (options.on_frame) options.on_frame(report.frames, frame, r);
    }
    // A keyframe held back for its next frame (map_features.source = tracker).
    if (const std::optional<SlamFrameResult> last = system->Flush()) Record(*last, &report);
  } catch (const std::exception& e) {
    report.input_error = e.what();
  }
  return report;
}

size_t MapPayloadBytes(const HybridMap& map) {
  size_t bytes = 0;
  for (const Keyframe& kf : map.keyframes()) {
    bytes += sizeof(Keyframe);
    bytes += kf.keypoints.size() * sizeof(cv::KeyPoint);
    bytes += kf.descriptors.total() * kf.descriptors.elemSize();
    bytes += kf.points_m.size() * sizeof(Eigen::Vector3d);
  }
  bytes += map.links().size() * sizeof(Link);
  return bytes;
}

std::string FormatSlamReport(const SlamRunReport& report, const SlamSystem& system) {
  std::string out;
  char line[256];
  auto add = [&](const char* fmt, auto... v) {
    std::snprintf(line, sizeof(line), fmt, v...);
    out += line;
  };
  const HybridMap& map = system.map();
  add("frames %zu, front-end keyframes %zu, map keyframes %zu (map total %d in %zu sessions)\n",
      report.frames, report.keyframes, report.map_keyframes, map.size(), map.sessions().size());
  add("loop closure: %zu queries, %zu registrations, %zu closures\n", report.loop_queries,
      report.loop_registrations, report.loop_closures);
  add("%-26s %8s %8s %8s\n", "stage [ms]", "mean", "median", "p95");
  const std::pair<const char*, const std::vector<double>*> stages[] = {
      {"features", &report.times.features},
      {"matching", &report.times.matching},
      {"icgm", &report.times.icgm},
      {"registration", &report.times.registration},
      {"fusion", &report.times.fusion},
      {"front end total", &report.times.frontend_total},
      {"map update / keyframe", &report.times.map_update},
      {"  loop registration / kf", &report.times.loop_registration},
      {"total per frame", &report.times.frame_total}};
  for (const auto& [name, v] : stages) {
    const Summary s = Summarize(*v);
    add("%-26s %8.2f %8.2f %8.2f\n", name, s.mean, s.median, s.p95);
  }
  size_t features = 0;
  for (const Keyframe& kf : map.keyframes()) features += kf.keypoints.size();
  if (!map.empty()) {
    add("map memory: %.1f KiB per keyframe (%.0f ICGM features per keyframe), %.2f MiB total\n",
        MapPayloadBytes(map) / 1024.0 / map.size(), static_cast<double>(features) / map.size(),
        MapPayloadBytes(map) / (1024.0 * 1024.0));
  }
  for (const auto& [why, n] : report.input_problems)
    add("  input problem %4zu x: %s\n", n, why.c_str());
  for (const auto& [why, n] : report.map_problems)
    add("  keyframe refused %4zu x: %s\n", n, why.c_str());
  if (!report.input_error.empty()) add("input ended early: %s\n", report.input_error.c_str());
  return out;
}

TumSlamInput LoadTumSlamInput(const std::string& config_dir, const std::string& tum_dir,
                              const std::string& camera_path) {
  TumSlamInput input;
  input.options = LoadSlamOptions(config_dir);
  input.dataset =
      std::make_shared<TumDataset>(TumDataset::Open(tum_dir, LoadCameraIntrinsics(camera_path)));
  return input;
}

}  // namespace icgm
