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
// Frame stamps: the Kinect's 60 MHz frame clock, unwrapped, in microseconds. An unplugged
// Kinect is disconnected (and announced again when plugged in); the end of fakenect's recording
// is OpenNI's end-of-file device state, raised once (fakenect plays its recording once).
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

#include "core/sensor/kinect_disparity.h"
#include "core/sensor/oni_rgbd_driver.h"

namespace icgm::kinect_driver {
namespace {

constexpr char kScheme[] = "freenect://";
constexpr int kWidth = 640, kHeight = 480, kFps = 30;
// Kinect v1 pinholes at 640x480 (ROS openni drivers' defaults): fields of view of the streams.
constexpr double kColorFocalPx = 525.0, kDepthFocalPx = 575.8157;

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

// A stream whose depth has the colour camera's view while registered.
class Stream : public oni_driver::RgbdStream {
 public:
  Stream(OniSensorType type, const OniVideoMode& mode,
         const std::atomic<OniImageRegistrationMode>* registration)
      : RgbdStream(type, mode, kColorFocalPx, kColorFocalPx, static_cast<int>(kKinectMaxDepthMm)),
        registration_(registration) {}

  // One frame from libfreenect: RGB888, millimetres, or raw 11-bit values (converted).
  void SendFreenect(const void* data, bool raw_depth, uint64_t device_us, int index) {
    Send(
        [&](void* out) {
          const int n = kWidth * kHeight;
          if (raw_depth) {
            KinectRawToMm(static_cast<const uint16_t*>(data), static_cast<uint16_t*>(out), n);
          } else {
            std::memcpy(out, data, n * bytes_per_pixel());
          }
        },
        device_us, index);
  }

 protected:
  double focal_px(bool) const override {
    const bool colour_view =
        type() == ONI_SENSOR_COLOR || *registration_ != ONI_IMAGE_REGISTRATION_OFF;
    return colour_view ? kColorFocalPx : kDepthFocalPx;
  }

 private:
  const std::atomic<OniImageRegistrationMode>* registration_;
};

class Device : public oni_driver::RgbdDevice<Stream> {
 public:
  Device(freenect_device* dev, int index, bool library_registers, OniDeviceInfo info)
      : RgbdDevice(
            kWidth, kHeight, kFps,
            library_registers ? ONI_IMAGE_REGISTRATION_DEPTH_TO_COLOR : ONI_IMAGE_REGISTRATION_OFF),
        dev_(dev),
        index_(index),
        library_registers_(library_registers),
        info_(info) {
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

  // Event thread: starts and stops libfreenect's streams as OpenNI's are, and switches the
  // depth mode to the registration asked for. True while any stream runs (events needed).
  bool Apply() {
    std::lock_guard<std::mutex> lock(mutex_);
    Stream* color = stream(true);
    Stream* depth = stream(false);
    const bool want_video = color != nullptr && color->running();
    const bool want_depth = depth != nullptr && depth->running();
    const bool registered = this->registered();
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
    const bool both_created = color != nullptr && depth != nullptr;
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

 protected:
  Stream* NewStream(OniSensorType type, const OniVideoMode& mode) override {
    return new Stream(type, mode, &registration());
  }
  // Registered depth comes from libfreenect's own registration only.
  bool RegistrationOffered(OniImageRegistrationMode mode) const override {
    return mode == ONI_IMAGE_REGISTRATION_OFF || library_registers_;
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
    Stream* s = stream(color);
    if (s != nullptr) {
      s->SendFreenect(data, !color && !library_registers_, device_us,
                      color ? color_index_++ : depth_index_++);
    }
  }

  freenect_device* dev_;
  const int index_;
  const bool library_registers_;
  OniDeviceInfo info_;
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
    if (index < 0) return ONI_STATUS_ERROR;  // not ours
    if (ctx_ == nullptr) {
      getServices().errorLoggerAppend("libfreenect could not be initialised (no USB access?)");
      return ONI_STATUS_ERROR;
    }
    const int connected = freenect_num_devices(ctx_);
    if (index >= connected) {
      getServices().errorLoggerAppend("no Kinect v1 at index %d (%d connected)", index, connected);
      return ONI_STATUS_ERROR;
    }
    Announce(index);
    return ONI_STATUS_OK;
  }
  oni::driver::DeviceBase* deviceOpen(const char* uri, const char*) override {
    const int index = ParseIndex(uri);
    if (index < 0) return nullptr;
    if (ctx_ == nullptr) {
      getServices().errorLoggerAppend("libfreenect could not be initialised (no USB access?)");
      return nullptr;
    }
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

  // Serves libfreenect's events while a stream runs. Events failing for a second disconnect the
  // open devices (unplugged); on fakenect, failing events are the end of its recording, which
  // is said once (device state EOF) while the devices stay open. While idle, devices plugged in
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
        if (streaming && !recording_ended_) {
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
      if (recording_ended_) {
        std::this_thread::sleep_for(std::chrono::milliseconds(10));
        continue;
      }
      if (status >= 0) {
        failing = false;
        continue;
      }
      if (!library_registers_) {
        EndOfRecording();
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

  // fakenect plays its recording once per process: the open devices get OpenNI's end-of-file
  // state, once, and no more events are served.
  void EndOfRecording() {
    std::vector<OniDeviceInfo> ended;
    {
      std::lock_guard<std::mutex> lock(mutex_);
      recording_ended_ = true;
      for (Device* d : devices_) ended.push_back(d->info());
    }
    for (const OniDeviceInfo& info : ended) deviceStateChanged(&info, ONI_DEVICE_STATE_EOF);
  }

  freenect_context* ctx_ = nullptr;
  // The real libfreenect registers; fakenect (replaying a recording) does not.
  bool library_registers_ = false;
  bool recording_ended_ = false;  // fakenect only; set on the event thread
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
