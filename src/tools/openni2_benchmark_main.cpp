// CPU per frame of the OpenNI2 driver path at the device's rate: OpenNI frames -> stamped,
// paired BGR / 16UC1 mm images (core/sensor/openni_camera.h) -> the four ROS messages the
// openni2_camera nodelet publishes (ros_bridge conversions; no ROS master needed). The virtual
// device's own cost (decoding the TUM images) is not counted: a real device has none.
#include <time.h>

#include <algorithm>
#include <chrono>
#include <condition_variable>
#include <cstdio>
#include <memory>
#include <mutex>
#include <vector>

#include "core/common/progress_bar.h"
#include "core/common/thread_cpu_time.h"
#include "core/dataset/camera_options.h"
#include "core/sensor/depth_registration.h"
#include "core/sensor/openni_camera.h"
#include "ros_bridge/conversions.h"
#include "tools/cli_args.h"

namespace {

const icgm::tools::ToolInfo kTool{
    "icgm_openni2_benchmark",
    "usage: icgm_openni2_benchmark --uri URI [--frames 300] [--camera_config YAML]\n"
    "  Opens an OpenNI2 device (\"\" = the first one; a .oni file; the virtual device\n"
    "  icgm-virtual://tum?dir=/path/to/tum_folder) and prints the driver's CPU time per frame:\n"
    "  frame conversion, clock mapping and pairing on OpenNI's threads, plus building the\n"
    "  colour, depth and camera_info messages, as the openni2_camera nodelet does. With a\n"
    "  camera YAML holding a depth_camera section, the depth is also registered to colour in\n"
    "  software (as the nodelet does for a device without hardware registration).\n"};

using icgm::ThreadCpuMs;

icgm::Time Now() {
  return icgm::Time::FromNanoseconds(std::chrono::duration_cast<std::chrono::nanoseconds>(
                                         std::chrono::steady_clock::now().time_since_epoch())
                                         .count());
}

}  // namespace

int main(int argc, char** argv) {
  using namespace icgm;
  std::string uri, camera_config;
  int frames = 300;
  try {
    const tools::CliArgs args(argc, argv, {"uri", "frames", "camera_config"}, {});
    if (args.help()) return tools::PrintUsage(kTool);
    uri = args.Require("uri");
    frames = args.GetInt("frames", 300);
    camera_config = args.Get("camera_config", "");
    if (frames < 10) throw std::invalid_argument("--frames must be >= 10");
  } catch (const std::invalid_argument& e) {
    return tools::UsageError(kTool, e.what());
  }
  std::unique_ptr<DepthRegistration> registration;
  if (!camera_config.empty()) {
    try {
      DepthCameraCalibration depth_camera;
      if (!LoadDepthCameraCalibration(camera_config, &depth_camera)) {
        return tools::Failure(kTool, "'" + camera_config + "' has no depth_camera section");
      }
      registration = std::make_unique<DepthRegistration>(depth_camera,
                                                         LoadCameraIntrinsics(camera_config));
    } catch (const LoadError& e) {
      return tools::Failure(kTool, e.what());
    }
  }
  OpenniCameraOptions options;
  options.uri = uri;
  OpenniCamera camera;
  std::mutex mutex;
  std::condition_variable done;
  std::vector<double> message_ms;
  CameraIntrinsics k;
  ProgressBar progress(frames, "frames");
  const Status opened = camera.Open(options, Now, [&](const RgbdPair& p) {
    const double start = ThreadCpuMs();
    const std::string frame = "camera_rgb_optical_frame";
    const auto rgb = ros_bridge::ToImageMsg(p.color.image, "bgr8", frame, p.color.stamp);
    const cv::Mat depth_mm = registration ? registration->Register(p.depth.image) : p.depth.image;
    const auto depth = ros_bridge::ToImageMsg(depth_mm, "16UC1", frame, p.depth.stamp);
    const auto info1 = ros_bridge::ToCameraInfo(k, frame, p.color.stamp);
    const auto info2 = ros_bridge::ToCameraInfo(k, frame, p.depth.stamp);
    const double ms = ThreadCpuMs() - start;
    (void)rgb, (void)depth, (void)info1, (void)info2;
    std::lock_guard<std::mutex> lock(mutex);
    if (static_cast<int>(message_ms.size()) < frames) {
      message_ms.push_back(ms);
      progress.Update(message_ms.size());
    }
    done.notify_all();
  });
  if (!opened.ok()) return tools::Failure(kTool, opened.reason());
  k = camera.FieldOfViewIntrinsics();
  if (Status s = camera.Start(); !s.ok()) return tools::Failure(kTool, s.reason());
  const auto start = std::chrono::steady_clock::now();
  {
    std::unique_lock<std::mutex> lock(mutex);
    done.wait_for(lock, std::chrono::seconds(frames / 5 + 20),
                  [&] { return static_cast<int>(message_ms.size()) >= frames; });
  }
  const double wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  const double frame_ms = camera.frame_cpu_ms();
  const size_t pairs = camera.pairs();
  camera.Close();
  progress.Finish();
  if (message_ms.empty() || pairs == 0) return tools::Failure(kTool, "no frames from '" + uri + "'");
  std::vector<double> sorted = message_ms;
  std::sort(sorted.begin(), sorted.end());
  double sum = 0.0;
  for (double v : message_ms) sum += v;
  const double convert = frame_ms / static_cast<double>(pairs);
  const double messages = sum / message_ms.size();
  std::printf("%zu pairs in %.1f s (%.1f Hz)\n", pairs, wall_s, pairs / wall_s);
  std::printf("frames -> paired images: %.2f ms CPU per frame\n", convert);
  std::printf("images -> 4 messages:    %.2f ms CPU per frame (p95 %.2f)%s\n", messages,
              sorted[sorted.size() * 95 / 100],
              registration ? ", depth registered in software" : "");
  std::printf("driver total:            %.2f ms CPU per frame (target <= 5 ms)\n", convert + messages);
  return 0;
}
