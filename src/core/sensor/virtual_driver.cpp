// The project's virtual OpenNI2 device driver (OniDriverAPI): a device that plays a TUM RGB-D
// folder or a simulated scenario (virtual_frame_source.h) in real time through OpenNI2, with a 640x480 @ 30 Hz RGB888 colour
// stream and a DEPTH_1_MM depth stream registered to colour, so the driver nodelet, OpenNI's
// Recorder and any OpenNI2 program treat it as a Kinect. Built as the shared library
// lib<...>.so.0 in the OpenNI2/Drivers folder next to the libOpenNI2 link of the build
// (src/core/sensor/module.cmake), where OpenNI2 looks for drivers.
#include <pthread.h>

#include <atomic>
#include <chrono>
#include <condition_variable>
#include <cstdlib>
#include <cstring>
#include <deque>
#include <memory>
#include <mutex>
#include <string>
#include <thread>

#include "core/sensor/oni_rgbd_driver.h"
#include "core/sensor/virtual_device_uri.h"
#include "core/sensor/virtual_frame_source.h"

namespace icgm::virtual_device {
namespace {

using oni_driver::RgbdStream;

class Device : public oni_driver::RgbdDevice<RgbdStream> {
 public:
  explicit Device(std::unique_ptr<VirtualFrameSource> source)
      : RgbdDevice(source->intrinsics().width_px, source->intrinsics().height_px, 30,
                   ONI_IMAGE_REGISTRATION_DEPTH_TO_COLOR),
        source_(std::move(source)) {
    loader_ = std::thread([this] { Load(); });
    // The decoding thread stands for the camera's hardware: named, so that CPU measurements of
    // the process can leave it out (a real device decodes nothing on the host).
    pthread_setname_np(loader_.native_handle(), kVirtualDeviceLoaderThread);
    thread_ = std::thread([this] { Run(); });
  }
  ~Device() override {
    {
      std::lock_guard<std::mutex> lock(loaded_mutex_);  // no waiter misses the quit
      quit_ = true;
    }
    loaded_changed_.notify_all();
    if (thread_.joinable()) thread_.join();
    if (loader_.joinable()) loader_.join();
  }

 protected:
  RgbdStream* NewStream(OniSensorType type, const OniVideoMode& mode) override {
    const CameraIntrinsics& k = source_->intrinsics();
    return new RgbdStream(type, mode, k.fx_px, k.fy_px, 10000);
  }
  // The TUM depth is registered already; "off" is accepted and changes nothing.
  bool RegistrationOffered(OniImageRegistrationMode) const override { return true; }

 private:
  // Events decoded ahead of their time, at most this many.
  static constexpr size_t kLoadAhead = 4;

  // Decodes the events in playback order (the order Run sends them in, wrapping with a looped
  // source) while fewer than kLoadAhead wait.
  void Load() {
    const auto& events = source_->events();
    size_t i = 0;
    while (!quit_) {
      if (i >= events.size()) {
        if (!source_->config().loop || events.empty()) return;
        i = 0;
      }
      {
        std::unique_lock<std::mutex> lock(loaded_mutex_);
        loaded_changed_.wait(lock, [this] { return quit_ || loaded_.size() < kLoadAhead; });
        if (quit_) return;
      }
      std::string error;
      cv::Mat image = source_->Load(events[i], &error);
      {
        std::lock_guard<std::mutex> lock(loaded_mutex_);
        loaded_.push_back(std::move(image));
      }
      loaded_changed_.notify_all();
      ++i;
    }
  }
  // The next decoded event's image (empty when it could not be read), or false on quit.
  bool NextLoaded(cv::Mat* image) {
    std::unique_lock<std::mutex> lock(loaded_mutex_);
    loaded_changed_.wait(lock, [this] { return quit_ || !loaded_.empty(); });
    if (quit_) return false;
    *image = std::move(loaded_.front());
    loaded_.pop_front();
    lock.unlock();
    loaded_changed_.notify_all();
    return true;
  }
  // Plays the events in real time (scaled by the rate) while a stream runs; the clock starts
  // when the first stream starts and pauses while none runs.
  void Run() {
    using Clock = std::chrono::steady_clock;
    const auto& events = source_->events();
    const double rate = source_->config().rate;
    size_t i = 0;
    int index = 0;
    bool playing = false;
    Clock::time_point origin;
    while (!quit_) {
      if (!AnyRunning()) {
        playing = false;
        std::this_thread::sleep_for(std::chrono::milliseconds(5));
        continue;
      }
      if (i >= events.size()) {
        if (!source_->config().loop) {
          std::this_thread::sleep_for(std::chrono::milliseconds(20));
          continue;
        }
        i = 0;
        playing = false;
      }
      const FrameEvent& e = events[i];
      const double since_first_s = (e.device_us - events.front().device_us) * 1e-6 / rate;
      if (!playing) {
        origin = Clock::now() - std::chrono::microseconds(static_cast<int64_t>(since_first_s * 1e6));
        playing = true;
      }
      const auto due = origin + std::chrono::microseconds(static_cast<int64_t>(since_first_s * 1e6));
      if (Clock::now() < due) {
        std::this_thread::sleep_for(std::min<Clock::duration>(due - Clock::now(), std::chrono::milliseconds(20)));
        continue;
      }
      cv::Mat image;
      if (!NextLoaded(&image)) break;
      if (!image.empty()) {
        std::lock_guard<std::mutex> lock(mutex_);
        RgbdStream* s = stream(e.color);
        // Looped playback keeps the device clock running forward.
        if (s != nullptr) {
          s->Send([&](void* data) { CopyRows(image, s->row_bytes(), data); },
                  e.device_us + loop_offset_us_, index);
        }
      }
      if (!e.color) ++index;
      ++i;
      if (i >= events.size() && source_->config().loop) {
        loop_offset_us_ += events.back().device_us + 33333;
      }
    }
  }
  static void CopyRows(const cv::Mat& image, int row_bytes, void* data) {
    for (int y = 0; y < image.rows; ++y) {
      std::memcpy(static_cast<char*>(data) + y * row_bytes, image.ptr(y), row_bytes);
    }
  }

  std::unique_ptr<VirtualFrameSource> source_;
  std::atomic<bool> quit_{false};
  uint64_t loop_offset_us_ = 0;
  std::mutex loaded_mutex_;
  std::condition_variable loaded_changed_;
  std::deque<cv::Mat> loaded_;
  std::thread loader_;
  std::thread thread_;
};

class Driver : public oni::driver::DriverBase {
 public:
  explicit Driver(OniDriverServices* services) : DriverBase(services) {}

  OniStatus initialize(oni::driver::DeviceConnectedCallback connected,
                       oni::driver::DeviceDisconnectedCallback disconnected,
                       oni::driver::DeviceStateChangedCallback state_changed,
                       void* cookie) override {
    DriverBase::initialize(connected, disconnected, state_changed, cookie);
    const char* env = std::getenv(kVirtualDeviceEnv);
    if (env != nullptr && IsVirtualDeviceUri(env)) tryDevice(env);
    return ONI_STATUS_OK;
  }
  OniStatus tryDevice(const char* uri) override {
    VirtualDeviceConfig config;
    if (uri == nullptr || !ParseVirtualDeviceUri(uri, &config).ok()) return ONI_STATUS_ERROR;
    OniDeviceInfo info{};
    std::strncpy(info.uri, uri, ONI_MAX_STR - 1);
    std::strncpy(info.vendor, "icgm_slam", ONI_MAX_STR - 1);
    std::strncpy(info.name, "virtual RGB-D device", ONI_MAX_STR - 1);
    deviceConnected(&info);
    return ONI_STATUS_OK;
  }
  oni::driver::DeviceBase* deviceOpen(const char* uri, const char*) override {
    VirtualDeviceConfig config;
    const Status parsed = ParseVirtualDeviceUri(uri == nullptr ? "" : uri, &config);
    if (!parsed.ok()) {
      getServices().errorLoggerAppend("%s", parsed.reason().c_str());
      return nullptr;
    }
    std::unique_ptr<VirtualFrameSource> source;
    const Status opened = OpenVirtualFrameSource(config, &source);
    if (!opened.ok()) {
      getServices().errorLoggerAppend("%s", opened.reason().c_str());
      return nullptr;
    }
    return new Device(std::move(source));
  }
  void deviceClose(oni::driver::DeviceBase* device) override { delete device; }
  void shutdown() override {}
};

}  // namespace
}  // namespace icgm::virtual_device

ONI_EXPORT_DRIVER(icgm::virtual_device::Driver)
