// The project's virtual OpenNI2 device driver (OniDriverAPI): a device that plays a TUM RGB-D
// folder or a simulated scenario (virtual_frame_source.h) in real time through OpenNI2, with a 640x480 @ 30 Hz RGB888 colour
// stream and a DEPTH_1_MM depth stream registered to colour, so the driver nodelet, OpenNI's
// Recorder and any OpenNI2 program treat it as a Kinect. Built as the shared library
// lib<...>.so.0 in the OpenNI2/Drivers folder next to the libOpenNI2 link of the build
// (src/core/sensor/module.cmake), where OpenNI2 looks for drivers.
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <memory>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#define XN_NEW(type, arg) new type(arg)
#define XN_DELETE(p) delete (p)
#include <Driver/OniDriverAPI.h>

#include "core/sensor/virtual_frame_source.h"
#include "core/sensor/virtual_device_uri.h"

namespace icgm::virtual_device {
namespace {

template <typename T>
OniStatus Put(const T& value, void* data, int* size) {
  if (*size < static_cast<int>(sizeof(T))) return ONI_STATUS_BAD_PARAMETER;
  std::memcpy(data, &value, sizeof(T));
  *size = sizeof(T);
  return ONI_STATUS_OK;
}

class Stream : public oni::driver::StreamBase {
 public:
  Stream(OniSensorType type, const CameraIntrinsics& k) : type_(type), k_(k) {
    mode_.pixelFormat = type == ONI_SENSOR_COLOR ? ONI_PIXEL_FORMAT_RGB888 : ONI_PIXEL_FORMAT_DEPTH_1_MM;
    mode_.resolutionX = k.width_px;
    mode_.resolutionY = k.height_px;
    mode_.fps = 30;
  }
  OniStatus start() override {
    running_ = true;
    return ONI_STATUS_OK;
  }
  void stop() override { running_ = false; }
  bool running() const { return running_; }
  const OniVideoMode& mode() const { return mode_; }
  int bytes_per_pixel() const { return type_ == ONI_SENSOR_COLOR ? 3 : 2; }

  OniBool isPropertySupported(int id) override {
    return id == ONI_STREAM_PROPERTY_VIDEO_MODE || id == ONI_STREAM_PROPERTY_HORIZONTAL_FOV ||
           id == ONI_STREAM_PROPERTY_VERTICAL_FOV || id == ONI_STREAM_PROPERTY_MAX_VALUE ||
           id == ONI_STREAM_PROPERTY_MIN_VALUE || id == ONI_STREAM_PROPERTY_STRIDE ||
           id == ONI_STREAM_PROPERTY_MIRRORING || id == ONI_STREAM_PROPERTY_CROPPING;
  }
  OniStatus getProperty(int id, void* data, int* size) override {
    switch (id) {
      case ONI_STREAM_PROPERTY_VIDEO_MODE: return Put(mode_, data, size);
      case ONI_STREAM_PROPERTY_HORIZONTAL_FOV:
        return Put(static_cast<float>(2.0 * std::atan(0.5 * k_.width_px / k_.fx_px)), data, size);
      case ONI_STREAM_PROPERTY_VERTICAL_FOV:
        return Put(static_cast<float>(2.0 * std::atan(0.5 * k_.height_px / k_.fy_px)), data, size);
      case ONI_STREAM_PROPERTY_MAX_VALUE: return Put(type_ == ONI_SENSOR_COLOR ? 255 : 10000, data, size);
      case ONI_STREAM_PROPERTY_MIN_VALUE: return Put(0, data, size);
      case ONI_STREAM_PROPERTY_STRIDE: return Put(mode_.resolutionX * bytes_per_pixel(), data, size);
      case ONI_STREAM_PROPERTY_MIRRORING: return Put(static_cast<OniBool>(FALSE), data, size);
      // OpenNI's Recorder writes the cropping state only for a stream that reports one, and its
      // file player drops every frame of a stream whose recording has none: report "off".
      case ONI_STREAM_PROPERTY_CROPPING: {
        OniCropping cropping{};
        cropping.enabled = FALSE;
        cropping.width = mode_.resolutionX;
        cropping.height = mode_.resolutionY;
        return Put(cropping, data, size);
      }
      default: return ONI_STATUS_NOT_SUPPORTED;
    }
  }
  OniStatus setProperty(int id, const void* data, int size) override {
    if (id == ONI_STREAM_PROPERTY_VIDEO_MODE && size == sizeof(OniVideoMode)) {
      const OniVideoMode* m = static_cast<const OniVideoMode*>(data);
      const bool same = m->pixelFormat == mode_.pixelFormat &&
                        m->resolutionX == mode_.resolutionX &&
                        m->resolutionY == mode_.resolutionY && m->fps == mode_.fps;
      return same ? ONI_STATUS_OK : ONI_STATUS_NOT_SUPPORTED;
    }
    if (id == ONI_STREAM_PROPERTY_MIRRORING && size == sizeof(OniBool)) {
      return *static_cast<const OniBool*>(data) ? ONI_STATUS_NOT_SUPPORTED : ONI_STATUS_OK;
    }
    if (id == ONI_STREAM_PROPERTY_CROPPING && size == sizeof(OniCropping)) {
      return static_cast<const OniCropping*>(data)->enabled ? ONI_STATUS_NOT_SUPPORTED : ONI_STATUS_OK;
    }
    return ONI_STATUS_NOT_SUPPORTED;
  }
  int getRequiredFrameSize() override {
    return mode_.resolutionX * mode_.resolutionY * bytes_per_pixel();
  }

  // Sends `image` (of the stream's type and size) stamped device_us.
  void Send(const cv::Mat& image, uint64_t device_us, int index) {
    if (!running_) return;
    OniFrame* frame = getServices().acquireFrame();
    if (frame == nullptr) return;
    const int row = mode_.resolutionX * bytes_per_pixel();
    for (int y = 0; y < mode_.resolutionY; ++y) {
      std::memcpy(static_cast<char*>(frame->data) + y * row, image.ptr(y), row);
    }
    frame->dataSize = row * mode_.resolutionY;
    frame->sensorType = type_;
    frame->timestamp = device_us;
    frame->frameIndex = index;
    frame->width = mode_.resolutionX;
    frame->height = mode_.resolutionY;
    frame->videoMode = mode_;
    frame->croppingEnabled = FALSE;
    frame->cropOriginX = 0;
    frame->cropOriginY = 0;
    frame->stride = row;
    raiseNewFrame(frame);
    getServices().releaseFrame(frame);
  }

 private:
  OniSensorType type_;
  CameraIntrinsics k_;
  OniVideoMode mode_{};
  std::atomic<bool> running_{false};
};

class Device : public oni::driver::DeviceBase {
 public:
  explicit Device(std::unique_ptr<VirtualFrameSource> source) : source_(std::move(source)) {
    const CameraIntrinsics& k = source_->intrinsics();
    for (OniSensorType t : {ONI_SENSOR_COLOR, ONI_SENSOR_DEPTH}) {
      OniVideoMode m{};
      m.pixelFormat = t == ONI_SENSOR_COLOR ? ONI_PIXEL_FORMAT_RGB888 : ONI_PIXEL_FORMAT_DEPTH_1_MM;
      m.resolutionX = k.width_px;
      m.resolutionY = k.height_px;
      m.fps = 30;
      modes_.push_back(m);
    }
    sensors_[0] = {ONI_SENSOR_COLOR, 1, &modes_[0]};
    sensors_[1] = {ONI_SENSOR_DEPTH, 1, &modes_[1]};
    thread_ = std::thread([this] { Run(); });
  }
  ~Device() override {
    quit_ = true;
    if (thread_.joinable()) thread_.join();
  }

  OniStatus getSensorInfoList(OniSensorInfo** infos, int* n) override {
    *infos = sensors_;
    *n = 2;
    return ONI_STATUS_OK;
  }
  oni::driver::StreamBase* createStream(OniSensorType type) override {
    if (type != ONI_SENSOR_COLOR && type != ONI_SENSOR_DEPTH) return nullptr;
    std::lock_guard<std::mutex> lock(mutex_);
    Stream*& slot = type == ONI_SENSOR_COLOR ? color_ : depth_;
    if (slot != nullptr) return nullptr;
    slot = new Stream(type, source_->intrinsics());
    return slot;
  }
  void destroyStream(oni::driver::StreamBase* stream) override {
    std::lock_guard<std::mutex> lock(mutex_);
    if (stream == color_) color_ = nullptr;
    if (stream == depth_) depth_ = nullptr;
    delete stream;
  }
  OniBool isImageRegistrationModeSupported(OniImageRegistrationMode) override { return TRUE; }
  OniBool isPropertySupported(int id) override { return id == ONI_DEVICE_PROPERTY_IMAGE_REGISTRATION; }
  OniStatus getProperty(int id, void* data, int* size) override {
    if (id != ONI_DEVICE_PROPERTY_IMAGE_REGISTRATION) return ONI_STATUS_NOT_SUPPORTED;
    return Put(registration_.load(), data, size);
  }
  OniStatus setProperty(int id, const void* data, int size) override {
    if (id != ONI_DEVICE_PROPERTY_IMAGE_REGISTRATION || size != sizeof(OniImageRegistrationMode)) {
      return ONI_STATUS_NOT_SUPPORTED;
    }
    // The TUM depth is registered already; "off" is accepted and changes nothing.
    registration_ = *static_cast<const OniImageRegistrationMode*>(data);
    return ONI_STATUS_OK;
  }

 private:
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
      std::string error;
      const cv::Mat image = source_->Load(e, &error);
      if (!image.empty()) {
        std::lock_guard<std::mutex> lock(mutex_);
        Stream* s = e.color ? color_ : depth_;
        // Looped playback keeps the device clock running forward.
        if (s != nullptr) s->Send(image, e.device_us + loop_offset_us_, index);
      }
      if (!e.color) ++index;
      ++i;
      if (i >= events.size() && source_->config().loop) {
        loop_offset_us_ += events.back().device_us + 33333;
      }
    }
  }
  bool AnyRunning() {
    std::lock_guard<std::mutex> lock(mutex_);
    return (color_ != nullptr && color_->running()) || (depth_ != nullptr && depth_->running());
  }

  std::unique_ptr<VirtualFrameSource> source_;
  std::vector<OniVideoMode> modes_;
  OniSensorInfo sensors_[2];
  std::mutex mutex_;
  Stream* color_ = nullptr;
  Stream* depth_ = nullptr;
  std::atomic<OniImageRegistrationMode> registration_{ONI_IMAGE_REGISTRATION_DEPTH_TO_COLOR};
  std::atomic<bool> quit_{false};
  uint64_t loop_offset_us_ = 0;
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
