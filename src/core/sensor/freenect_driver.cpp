// The project's OpenNI2 driver for the Kinect v1 (Xbox 360 Kinect), on libfreenect
// (OniDriverAPI): OpenNI2 programs, the driver nodelet among them, open a Kinect v1 as
// "freenect://<index>" (index 0, 1, ... in libfreenect's order; the first one is announced as a
// device, so "the first device" finds it). Colour: 640x480 @ 30 Hz RGB888. Depth: 640x480 @ 30
// Hz DEPTH_1_MM, registered to colour by libfreenect (FREENECT_DEPTH_REGISTERED, its host-side
// registration with the device's own calibration) while OpenNI's image registration is
// DEPTH_TO_COLOR (the default), unregistered millimetres (FREENECT_DEPTH_MM) while it is OFF.
// A libfreenect without those modes (fakenect, which replays a recorded dump and offers the raw
// 11-bit mode only) gives the raw values converted to millimetres (kinect_disparity.h) and no
// registration: the driver nodelet then registers in software (depth_registration.h).
// Frame stamps: the Kinect's 60 MHz frame clock, unwrapped, in microseconds.
//
// All libfreenect calls except opening and closing a device run on one thread, which serves
// libfreenect's events while a stream runs (fakenect consumes its dump as events are served).
// Built as lib<...>.so.0 in the OpenNI2/Drivers folder of the build when libfreenect is
// installed (src/core/sensor/module.cmake).
#include <dlfcn.h>
#include <sys/time.h>

#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <mutex>
#include <set>
#include <string>
#include <thread>
#include <vector>

#include <libfreenect.h>

#define XN_NEW(type, arg) new type(arg)
#define XN_DELETE(p) delete (p)
#include <Driver/OniDriverAPI.h>

#include "core/sensor/kinect_disparity.h"

namespace icgm::kinect_driver {
namespace {

constexpr char kScheme[] = "freenect://";
constexpr int kWidth = 640, kHeight = 480, kFps = 30;
// Kinect v1 pinholes at 640x480 (ROS openni drivers' defaults): fields of view of the streams.
constexpr double kColorFocalPx = 525.0, kDepthFocalPx = 575.8157;

template <typename T>
OniStatus Put(const T& value, void* data, int* size) {
  if (*size < static_cast<int>(sizeof(T))) return ONI_STATUS_BAD_PARAMETER;
  std::memcpy(data, &value, sizeof(T));
  *size = sizeof(T);
  return ONI_STATUS_OK;
}

// The device index of "freenect://<index>"; -1 for any other URI.
int ParseIndex(const char* uri) {
  if (uri == nullptr || std::strncmp(uri, kScheme, sizeof(kScheme) - 1) != 0) return -1;
  const char* digits = uri + sizeof(kScheme) - 1;
  if (*digits == '\0' || std::strspn(digits, "0123456789") != std::strlen(digits)) return -1;
  return std::atoi(digits);
}

// Whether the libfreenect this driver was loaded with registers depth to colour (the real
// library does; fakenect does not and offers only the raw 11-bit depth mode).
bool LibraryRegisters(std::string* path) {
  Dl_info info{};
  if (dladdr(reinterpret_cast<void*>(&freenect_init), &info) == 0 || info.dli_fname == nullptr) {
    return false;
  }
  *path = info.dli_fname;
  void* lib = dlopen(info.dli_fname, RTLD_LAZY | RTLD_NOLOAD);
  if (lib == nullptr) return false;
  const bool registers = dlsym(lib, "freenect_copy_registration") != nullptr;
  dlclose(lib);
  return registers;
}

OniVideoMode Mode(OniSensorType type) {
  OniVideoMode m{};
  m.pixelFormat = type == ONI_SENSOR_COLOR ? ONI_PIXEL_FORMAT_RGB888 : ONI_PIXEL_FORMAT_DEPTH_1_MM;
  m.resolutionX = kWidth;
  m.resolutionY = kHeight;
  m.fps = kFps;
  return m;
}

class Device;

class Stream : public oni::driver::StreamBase {
 public:
  Stream(OniSensorType type, const std::atomic<bool>* registered)
      : type_(type), mode_(Mode(type)), registered_(registered) {}
  OniStatus start() override {
    running_ = true;
    return ONI_STATUS_OK;
  }
  void stop() override { running_ = false; }
  bool running() const { return running_; }
  int bytes_per_pixel() const { return type_ == ONI_SENSOR_COLOR ? 3 : 2; }

  OniBool isPropertySupported(int id) override {
    return id == ONI_STREAM_PROPERTY_VIDEO_MODE || id == ONI_STREAM_PROPERTY_HORIZONTAL_FOV ||
           id == ONI_STREAM_PROPERTY_VERTICAL_FOV || id == ONI_STREAM_PROPERTY_MAX_VALUE ||
           id == ONI_STREAM_PROPERTY_MIN_VALUE || id == ONI_STREAM_PROPERTY_STRIDE ||
           id == ONI_STREAM_PROPERTY_MIRRORING || id == ONI_STREAM_PROPERTY_CROPPING;
  }
  OniStatus getProperty(int id, void* data, int* size) override {
    // Registered depth has the colour camera's view.
    const double f = type_ == ONI_SENSOR_COLOR || registered_->load() ? kColorFocalPx : kDepthFocalPx;
    switch (id) {
      case ONI_STREAM_PROPERTY_VIDEO_MODE: return Put(mode_, data, size);
      case ONI_STREAM_PROPERTY_HORIZONTAL_FOV:
        return Put(static_cast<float>(2.0 * std::atan(0.5 * kWidth / f)), data, size);
      case ONI_STREAM_PROPERTY_VERTICAL_FOV:
        return Put(static_cast<float>(2.0 * std::atan(0.5 * kHeight / f)), data, size);
      case ONI_STREAM_PROPERTY_MAX_VALUE:
        return Put(type_ == ONI_SENSOR_COLOR ? 255 : static_cast<int>(kKinectMaxDepthMm), data, size);
      case ONI_STREAM_PROPERTY_MIN_VALUE: return Put(0, data, size);
      case ONI_STREAM_PROPERTY_STRIDE: return Put(kWidth * bytes_per_pixel(), data, size);
      case ONI_STREAM_PROPERTY_MIRRORING: return Put(static_cast<OniBool>(FALSE), data, size);
      case ONI_STREAM_PROPERTY_CROPPING: {  // "off": OpenNI's Recorder and file player need one
        OniCropping cropping{};
        cropping.width = kWidth;
        cropping.height = kHeight;
        return Put(cropping, data, size);
      }
      default: return ONI_STATUS_NOT_SUPPORTED;
    }
  }
  OniStatus setProperty(int id, const void* data, int size) override {
    if (id == ONI_STREAM_PROPERTY_VIDEO_MODE && size == sizeof(OniVideoMode)) {
      const OniVideoMode* m = static_cast<const OniVideoMode*>(data);
      const bool same = m->pixelFormat == mode_.pixelFormat && m->resolutionX == kWidth &&
                        m->resolutionY == kHeight && m->fps == kFps;
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
  int getRequiredFrameSize() override { return kWidth * kHeight * bytes_per_pixel(); }

  // One frame from libfreenect: RGB888, millimetres, or raw 11-bit values (converted).
  void Send(const void* data, bool raw_depth, uint64_t device_us, int index) {
    if (!running_) return;
    OniFrame* frame = getServices().acquireFrame();
    if (frame == nullptr) return;
    const int n = kWidth * kHeight;
    if (raw_depth) {
      KinectRawToMm(static_cast<const uint16_t*>(data), static_cast<uint16_t*>(frame->data), n);
    } else {
      std::memcpy(frame->data, data, n * bytes_per_pixel());
    }
    frame->dataSize = n * bytes_per_pixel();
    frame->sensorType = type_;
    frame->timestamp = device_us;
    frame->frameIndex = index;
    frame->width = kWidth;
    frame->height = kHeight;
    frame->videoMode = mode_;
    frame->croppingEnabled = FALSE;
    frame->cropOriginX = 0;
    frame->cropOriginY = 0;
    frame->stride = kWidth * bytes_per_pixel();
    raiseNewFrame(frame);
    getServices().releaseFrame(frame);
  }

 private:
  OniSensorType type_;
  OniVideoMode mode_;
  const std::atomic<bool>* registered_;
  std::atomic<bool> running_{false};
};

class Device : public oni::driver::DeviceBase {
 public:
  Device(freenect_device* dev, int index, bool library_registers, OniDeviceInfo info)
      : dev_(dev), index_(index), library_registers_(library_registers), info_(info) {
    modes_[0] = Mode(ONI_SENSOR_COLOR);
    modes_[1] = Mode(ONI_SENSOR_DEPTH);
    sensors_[0] = {ONI_SENSOR_COLOR, 1, &modes_[0]};
    sensors_[1] = {ONI_SENSOR_DEPTH, 1, &modes_[1]};
    registered_ = library_registers_;
    freenect_set_user(dev_, this);
    freenect_set_video_callback(dev_, [](freenect_device* d, void* data, uint32_t ticks) {
      static_cast<Device*>(freenect_get_user(d))->OnFrame(true, data, ticks);
    });
    freenect_set_depth_callback(dev_, [](freenect_device* d, void* data, uint32_t ticks) {
      static_cast<Device*>(freenect_get_user(d))->OnFrame(false, data, ticks);
    });
  }
  ~Device() override {
    if (video_on_) freenect_stop_video(dev_);
    if (depth_on_) freenect_stop_depth(dev_);
    freenect_close_device(dev_);
  }
  const OniDeviceInfo& info() const { return info_; }
  int index() const { return index_; }

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
    slot = new Stream(type, &registered_);
    return slot;
  }
  void destroyStream(oni::driver::StreamBase* stream) override {
    std::lock_guard<std::mutex> lock(mutex_);
    if (stream == color_) color_ = nullptr;
    if (stream == depth_) depth_ = nullptr;
    delete stream;
  }
  OniBool isImageRegistrationModeSupported(OniImageRegistrationMode mode) override {
    return mode == ONI_IMAGE_REGISTRATION_OFF || library_registers_;
  }
  OniBool isPropertySupported(int id) override { return id == ONI_DEVICE_PROPERTY_IMAGE_REGISTRATION; }
  OniStatus getProperty(int id, void* data, int* size) override {
    if (id != ONI_DEVICE_PROPERTY_IMAGE_REGISTRATION) return ONI_STATUS_NOT_SUPPORTED;
    return Put(registered_ ? ONI_IMAGE_REGISTRATION_DEPTH_TO_COLOR : ONI_IMAGE_REGISTRATION_OFF,
               data, size);
  }
  OniStatus setProperty(int id, const void* data, int size) override {
    if (id != ONI_DEVICE_PROPERTY_IMAGE_REGISTRATION || size != sizeof(OniImageRegistrationMode)) {
      return ONI_STATUS_NOT_SUPPORTED;
    }
    const bool on = *static_cast<const OniImageRegistrationMode*>(data) != ONI_IMAGE_REGISTRATION_OFF;
    if (on && !library_registers_) return ONI_STATUS_NOT_SUPPORTED;
    registered_ = on;  // the event thread switches the depth mode
    return ONI_STATUS_OK;
  }

  // Event thread: starts and stops libfreenect's streams as OpenNI's are, and switches the
  // depth mode to the registration asked for. True while any stream runs (events needed).
  bool Apply() {
    std::lock_guard<std::mutex> lock(mutex_);
    const bool want_video = color_ != nullptr && color_->running();
    const bool want_depth = depth_ != nullptr && depth_->running();
    const bool registered = registered_;
    if (depth_on_ && (!want_depth || registered != depth_registered_)) {
      freenect_stop_depth(dev_);
      depth_on_ = false;
    }
    if (video_on_ && !want_video) {
      freenect_stop_video(dev_);
      video_on_ = false;
    }
    // Both streams start together when both run (fakenect plays its dump from the first
    // event served on, so neither misses the first frames).
    const bool both_created = color_ != nullptr && depth_ != nullptr;
    if (both_created && want_video != want_depth && !video_on_ && !depth_on_) return false;
    if (want_video && !video_on_) {
      freenect_set_video_mode(dev_, freenect_find_video_mode(FREENECT_RESOLUTION_MEDIUM, FREENECT_VIDEO_RGB));
      video_on_ = freenect_start_video(dev_) == 0;
    }
    if (want_depth && !depth_on_) {
      const freenect_depth_format format =
          !library_registers_ ? FREENECT_DEPTH_11BIT
                              : (registered ? FREENECT_DEPTH_REGISTERED : FREENECT_DEPTH_MM);
      freenect_set_depth_mode(dev_, freenect_find_depth_mode(FREENECT_RESOLUTION_MEDIUM, format));
      depth_on_ = freenect_start_depth(dev_) == 0;
      depth_registered_ = registered;
    }
    return video_on_ || depth_on_;
  }

 private:
  void OnFrame(bool color, const void* data, uint32_t ticks) {
    // Unwrap the 32-bit 60 MHz clock (shared by both streams, whose frames may arrive slightly
    // out of order).
    if (!clock_started_) {
      ticks_ = ticks;
      clock_started_ = true;
    } else {
      ticks_ += static_cast<int32_t>(ticks - last_ticks_);
    }
    last_ticks_ = ticks;
    const uint64_t device_us = ticks_ > 0 ? static_cast<uint64_t>(ticks_) / 60 : 0;
    std::lock_guard<std::mutex> lock(mutex_);
    Stream* s = color ? color_ : depth_;
    if (s != nullptr) {
      s->Send(data, !color && !library_registers_, device_us, color ? color_index_++ : depth_index_++);
    }
  }

  freenect_device* dev_;
  const int index_;
  const bool library_registers_;
  OniDeviceInfo info_;
  OniVideoMode modes_[2];
  OniSensorInfo sensors_[2];
  std::mutex mutex_;
  Stream* color_ = nullptr;
  Stream* depth_ = nullptr;
  std::atomic<bool> registered_{false};
  // Event thread only:
  bool video_on_ = false, depth_on_ = false, depth_registered_ = false;
  bool clock_started_ = false;
  uint32_t last_ticks_ = 0;
  int64_t ticks_ = 0;
  int color_index_ = 0, depth_index_ = 0;
};

class Driver : public oni::driver::DriverBase {
 public:
  explicit Driver(OniDriverServices* services) : DriverBase(services) {}
  ~Driver() override { shutdown(); }

  OniStatus initialize(oni::driver::DeviceConnectedCallback connected,
                       oni::driver::DeviceDisconnectedCallback disconnected,
                       oni::driver::DeviceStateChangedCallback state_changed,
                       void* cookie) override {
    DriverBase::initialize(connected, disconnected, state_changed, cookie);
    if (freenect_init(&ctx_, nullptr) < 0) {
      ctx_ = nullptr;
      return ONI_STATUS_OK;  // no USB access: no Kinect, the other drivers still work
    }
    freenect_set_log_level(ctx_, FREENECT_LOG_ERROR);
    freenect_select_subdevices(ctx_, FREENECT_DEVICE_CAMERA);
    library_registers_ = LibraryRegisters(&library_path_);
    const int n = freenect_num_devices(ctx_);
    for (int i = 0; i < n; ++i) Announce(i);
    quit_ = false;
    thread_ = std::thread([this] { Run(); });
    return ONI_STATUS_OK;
  }
  OniStatus tryDevice(const char* uri) override {
    const int index = ParseIndex(uri);
    if (ctx_ == nullptr || index < 0 || index >= freenect_num_devices(ctx_)) return ONI_STATUS_ERROR;
    Announce(index);
    return ONI_STATUS_OK;
  }
  oni::driver::DeviceBase* deviceOpen(const char* uri, const char*) override {
    const int index = ParseIndex(uri);
    if (ctx_ == nullptr || index < 0) return nullptr;
    std::lock_guard<std::mutex> lock(mutex_);
    freenect_device* dev = nullptr;
    if (freenect_open_device(ctx_, &dev, index) < 0 || dev == nullptr) {
      getServices().errorLoggerAppend("libfreenect cannot open Kinect %d", index);
      return nullptr;
    }
    Device* device = new Device(dev, index, library_registers_, Info(index));
    devices_.push_back(device);
    return device;
  }
  void deviceClose(oni::driver::DeviceBase* device) override {
    std::lock_guard<std::mutex> lock(mutex_);
    for (size_t i = 0; i < devices_.size(); ++i) {
      if (devices_[i] == device) devices_.erase(devices_.begin() + i);
    }
    delete device;
  }
  void shutdown() override {
    quit_ = true;
    if (thread_.joinable()) thread_.join();
    std::lock_guard<std::mutex> lock(mutex_);
    for (Device* d : devices_) delete d;
    devices_.clear();
    if (ctx_ != nullptr) freenect_shutdown(ctx_);
    ctx_ = nullptr;
  }

 private:
  OniDeviceInfo Info(int index) const {
    OniDeviceInfo info{};
    std::snprintf(info.uri, ONI_MAX_STR, "%s%d", kScheme, index);
    std::strncpy(info.vendor, "Microsoft", ONI_MAX_STR - 1);
    std::snprintf(info.name, ONI_MAX_STR, "Kinect v1 (libfreenect%s)",
                  library_registers_ ? "" : " without registration");
    info.usbVendorId = 0x045e;
    info.usbProductId = 0x02ae;
    return info;
  }
  // Tells OpenNI about a device (never while holding mutex_: OpenNI may be calling deviceOpen,
  // which takes it, under its own lock).
  void Announce(int index) {
    {
      std::lock_guard<std::mutex> lock(mutex_);
      if (!announced_.insert(index).second) return;
    }
    OniDeviceInfo info = Info(index);
    deviceConnected(&info);
  }

  // Serves libfreenect's events while a stream runs. Events failing for a second (unplugged, or
  // the end of a fakenect dump) disconnect the open devices; while idle, devices plugged in
  // (again) are announced every second.
  void Run() {
    using Clock = std::chrono::steady_clock;
    Clock::time_point failing_since{}, last_scan = Clock::now();
    bool failing = false;
    while (!quit_) {
      bool streaming = false;
      int status = 0;
      {
        std::lock_guard<std::mutex> lock(mutex_);
        for (Device* d : devices_) streaming = d->Apply() || streaming;
        if (streaming) {
          timeval timeout{0, 50000};
          status = freenect_process_events_timeout(ctx_, &timeout);
        }
      }
      if (!streaming) {
        failing = false;
        if (Clock::now() - last_scan > std::chrono::seconds(1)) {
          last_scan = Clock::now();
          const int n = freenect_num_devices(ctx_);
          for (int i = 0; i < n; ++i) Announce(i);
        }
        std::this_thread::sleep_for(std::chrono::milliseconds(5));
        continue;
      }
      if (status >= 0) {
        failing = false;
        continue;
      }
      if (!failing) failing_since = Clock::now();
      failing = true;
      if (Clock::now() - failing_since > std::chrono::seconds(1)) {
        std::vector<OniDeviceInfo> lost;
        {
          std::lock_guard<std::mutex> lock(mutex_);
          for (Device* d : devices_) {
            lost.push_back(d->info());
            announced_.erase(d->index());
          }
        }
        for (const OniDeviceInfo& info : lost) deviceDisconnected(&info);
        failing = false;
      }
      std::this_thread::sleep_for(std::chrono::milliseconds(10));
    }
  }

  freenect_context* ctx_ = nullptr;
  bool library_registers_ = false;
  std::string library_path_;
  std::mutex mutex_;
  std::vector<Device*> devices_;
  std::set<int> announced_;  // indices OpenNI knows as connected
  std::atomic<bool> quit_{false};
  std::thread thread_;
};

}  // namespace
}  // namespace icgm::kinect_driver

ONI_EXPORT_DRIVER(icgm::kinect_driver::Driver)
