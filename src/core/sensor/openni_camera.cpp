#include "core/sensor/openni_camera.h"

#include <OpenNI.h>

#include <time.h>

#include <cctype>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <sstream>
#include <thread>
#include <utility>

#include <opencv2/imgproc.hpp>

#include "core/common/thread_cpu_time.h"

namespace icgm {
namespace {

bool EndsWith(const std::string& s, const std::string& suffix) {
  return s.size() >= suffix.size() && s.compare(s.size() - suffix.size(), suffix.size(), suffix) == 0;
}

}  // namespace

Status OpenniCameraOptions::Validate() const {
  if (width_px < 1 || height_px < 1 || width_px > 4096 || height_px > 4096) {
    return Status::Error("openni camera: image size not in [1, 4096]");
  }
  if (fps < 1 || fps > 120) return Status::Error("openni camera: fps not in [1, 120]");
  // A recording that is not there is refused up front, not retried as a device, unless asked to
  // wait for it.
  if (EndsWith(uri, ".oni") && !wait_for_recording && !std::filesystem::is_regular_file(uri)) {
    return Status::Error("openni camera: recording '" + uri +
                         "' does not exist (wait_for_recording to wait for it)");
  }
  if (!(max_sync_dt_s > 0.0 && max_sync_dt_s <= 1.0)) {
    return Status::Error("openni camera: max_sync_dt_s not in (0, 1]");
  }
  return clock.Validate();
}

CameraIntrinsics IntrinsicsFromFieldOfView(int width_px, int height_px, double hfov_rad,
                                           double vfov_rad) {
  CameraIntrinsics k;
  k.width_px = width_px;
  k.height_px = height_px;
  k.fx_px = 0.5 * width_px / std::tan(0.5 * hfov_rad);
  k.fy_px = 0.5 * height_px / std::tan(0.5 * vfov_rad);
  k.cx_px = 0.5 * (width_px - 1);
  k.cy_px = 0.5 * (height_px - 1);
  k.depth_scale = 1000.0;
  return k;
}

namespace {

// `what` and OpenNI's explanation on one line (OpenNI's has tabs and line breaks).
std::string Error(const std::string& what) {
  std::string detail;
  for (const char* c = openni::OpenNI::getExtendedError(); c != nullptr && *c != '\0'; ++c) {
    const bool space = std::isspace(static_cast<unsigned char>(*c)) != 0;
    if (space && (detail.empty() || detail.back() == ' ')) continue;
    detail += space ? ' ' : *c;
  }
  while (!detail.empty() && detail.back() == ' ') detail.pop_back();
  return detail.empty() ? what : what + ": " + detail;
}

// Chooses the video mode of `stream` nearest to the requested one with `format`.
bool SetMode(openni::VideoStream* stream, const OpenniCameraOptions& o,
             openni::PixelFormat format) {
  const auto& modes = stream->getSensorInfo().getSupportedVideoModes();
  for (int i = 0; i < modes.getSize(); ++i) {
    if (modes[i].getResolutionX() == o.width_px && modes[i].getResolutionY() == o.height_px &&
        modes[i].getFps() == o.fps && modes[i].getPixelFormat() == format) {
      return stream->setVideoMode(modes[i]) == openni::STATUS_OK;
    }
  }
  return false;
}

}  // namespace

class OpenniCamera::Impl : public openni::OpenNI::DeviceDisconnectedListener,
                           public openni::OpenNI::DeviceStateChangedListener {
 public:
  explicit Impl(OpenniCamera* owner) : owner_(owner), color_listener_(this), depth_listener_(this) {}

  // OpenNI's listener holds one callback registration: one listener per stream.
  struct Listener : public openni::VideoStream::NewFrameListener {
    explicit Listener(Impl* impl) : impl(impl) {}
    void onNewFrame(openni::VideoStream& stream) override { impl->OnFrame(stream); }
    Impl* impl;
  };

  void OnFrame(openni::VideoStream& stream) {
    const Time arrival = host_clock_();
    const double cpu_start_ms = ThreadCpuMs();
    openni::VideoFrameRef frame;
    if (stream.readFrame(&frame) != openni::STATUS_OK || !frame.isValid()) return;
    StampedImage image;
    image.device_us = frame.getTimestamp();
    const openni::PixelFormat format = frame.getVideoMode().getPixelFormat();
    const cv::Mat raw(frame.getHeight(), frame.getWidth(),
                      format == openni::PIXEL_FORMAT_RGB888 ? CV_8UC3 : CV_16UC1,
                      const_cast<void*>(frame.getData()), frame.getStrideInBytes());
    const bool is_color = frame.getSensorType() == openni::SENSOR_COLOR;
    if (is_color) {
      if (format != openni::PIXEL_FORMAT_RGB888) return;
      cv::cvtColor(raw, image.image, cv::COLOR_RGB2BGR);
    } else if (format == openni::PIXEL_FORMAT_DEPTH_1_MM) {
      image.image = raw.clone();
    } else if (format == openni::PIXEL_FORMAT_DEPTH_100_UM) {
      raw.convertTo(image.image, CV_16UC1, 0.1);
    } else {
      return;
    }
    std::optional<RgbdPair> pair;
    {
      std::lock_guard<std::mutex> lock(mutex_);
      image.stamp = clock_.Map(image.device_us, arrival);
      last_frame_ = arrival;
      last_activity_ = std::chrono::steady_clock::now();
      pair = is_color ? pairer_.AddColor(std::move(image)) : pairer_.AddDepth(std::move(image));
      if (pair) {
        // Both images of a pair on the estimate that has seen both arrivals: frames of one
        // device instant get one stamp even when the later-stamped one was read first.
        pair->color.stamp = clock_.ToHost(pair->color.device_us);
        pair->depth.stamp = clock_.ToHost(pair->depth.device_us);
      }
      cpu_ms_ += ThreadCpuMs() - cpu_start_ms;
    }
    if (pair) callback_(*pair);
  }

  void onDeviceDisconnected(const openni::DeviceInfo* info) override {
    if (info != nullptr && uri_ == info->getUri()) owner_->disconnected_ = true;
  }
  void onDeviceStateChanged(const openni::DeviceInfo* info, openni::DeviceState state) override {
    if (info != nullptr && uri_ == info->getUri() && state == openni::DEVICE_STATE_EOF) {
      ++owner_->recording_ends_;
    }
  }

  OpenniCamera* owner_;
  openni::Device device_;
  openni::VideoStream color_;
  openni::VideoStream depth_;
  openni::Recorder recorder_;
  Listener color_listener_;
  Listener depth_listener_;
  std::string uri_;
  std::string name_;
  bool listeners_added_ = false;
  HostClock host_clock_;
  PairCallback callback_;
  mutable std::mutex mutex_;
  DeviceClock clock_;
  FramePairer pairer_;
  Time last_frame_;
  std::chrono::steady_clock::time_point last_activity_;  // last frame or Start
  double cpu_ms_ = 0.0;
  OpenniCameraOptions options_;
};

OpenniCamera::OpenniCamera() = default;

OpenniCamera::~OpenniCamera() { Close(); }

Status OpenniCamera::Open(const OpenniCameraOptions& options, HostClock clock,
                          PairCallback callback) {
  Close();
  if (Status s = options.Validate(); !s.ok()) return s;
  if (openni::OpenNI::initialize() != openni::STATUS_OK) {
    return Status::Error(Error("cannot initialise OpenNI2"));
  }
  impl_ = std::make_unique<Impl>(this);
  Impl& d = *impl_;
  d.options_ = options;
  d.host_clock_ = std::move(clock);
  d.callback_ = std::move(callback);
  d.clock_ = DeviceClock(options.clock);
  d.pairer_ = FramePairer(options.max_sync_dt_s);
  disconnected_ = false;
  recording_ends_ = 0;
  if (options.uri.empty()) {
    openni::Array<openni::DeviceInfo> devices;
    openni::OpenNI::enumerateDevices(&devices);
    if (devices.getSize() == 0) {
      impl_.reset();
      return Status::Error("no OpenNI2 device connected (is the camera plugged in and powered?)");
    }
    d.uri_ = devices[0].getUri();
  } else {
    d.uri_ = options.uri;
  }
  if (d.device_.open(d.uri_.c_str()) != openni::STATUS_OK) {
    const std::string reason = Error("cannot open OpenNI2 device '" + d.uri_ + "'");
    impl_.reset();
    return Status::Error(reason);
  }
  d.name_ = d.device_.getDeviceInfo().getName();
  const bool recording = EndsWith(d.uri_, ".oni") || d.device_.isFile();
  if (d.color_.create(d.device_, openni::SENSOR_COLOR) != openni::STATUS_OK ||
      d.depth_.create(d.device_, openni::SENSOR_DEPTH) != openni::STATUS_OK) {
    const std::string reason = Error("device '" + d.uri_ + "' has no colour and depth streams");
    Close();
    return Status::Error(reason);
  }
  if (!recording && (!SetMode(&d.color_, options, openni::PIXEL_FORMAT_RGB888) ||
                     !SetMode(&d.depth_, options, openni::PIXEL_FORMAT_DEPTH_1_MM))) {
    std::ostringstream why;
    why << "device '" << d.uri_ << "' offers no " << options.width_px << "x"
        << options.height_px << " @ " << options.fps << " Hz RGB888 colour and 1 mm depth mode";
    Close();
    return Status::Error(why.str());
  }
  hardware_registration_ = false;
  if (recording) {
    hardware_registration_ = options.oni_registered;
  } else if (options.hardware_registration &&
             d.device_.isImageRegistrationModeSupported(openni::IMAGE_REGISTRATION_DEPTH_TO_COLOR)) {
    hardware_registration_ =
        d.device_.setImageRegistrationMode(openni::IMAGE_REGISTRATION_DEPTH_TO_COLOR) ==
        openni::STATUS_OK;
  }
  if (recording && d.device_.getPlaybackControl() != nullptr) {
    d.device_.getPlaybackControl()->setRepeatEnabled(options.oni_repeat);
  }
  if (options.hardware_sync) d.device_.setDepthColorSyncEnabled(true);  // best effort
  d.color_.addNewFrameListener(&d.color_listener_);
  d.depth_.addNewFrameListener(&d.depth_listener_);
  openni::OpenNI::addDeviceDisconnectedListener(&d);
  openni::OpenNI::addDeviceStateChangedListener(&d);
  d.listeners_added_ = true;
  return Status::Ok();
}

Status OpenniCamera::Start() {
  if (!impl_) return Status::Error("openni camera: not open");
  if (started_) return Status::Ok();
  {
    std::lock_guard<std::mutex> lock(impl_->mutex_);
    impl_->pairer_.Clear();
    // A device may pause its clock while stopped (a recording, the virtual device): the
    // mapping starts again with the streams.
    impl_->clock_ = DeviceClock(impl_->options_.clock);
    impl_->last_activity_ = std::chrono::steady_clock::now();
  }
  if (impl_->depth_.start() != openni::STATUS_OK || impl_->color_.start() != openni::STATUS_OK) {
    impl_->depth_.stop();
    return Status::Error(Error("cannot start the streams of '" + impl_->uri_ + "'"));
  }
  started_ = true;
  return Status::Ok();
}

void OpenniCamera::Stop() {
  if (!impl_ || !started_) return;
  impl_->color_.stop();
  impl_->depth_.stop();
  started_ = false;
}

Status OpenniCamera::StartRecording(const std::string& oni_path) {
  if (!impl_) return Status::Error("openni camera: not open");
  StopRecording();
  openni::Recorder& r = impl_->recorder_;
  if (r.create(oni_path.c_str()) != openni::STATUS_OK ||
      r.attach(impl_->color_, false) != openni::STATUS_OK ||
      r.attach(impl_->depth_, false) != openni::STATUS_OK || r.start() != openni::STATUS_OK) {
    const std::string reason = Error("cannot record to '" + oni_path + "'");
    r.destroy();
    return Status::Error(reason);
  }
  return Status::Ok();
}

void OpenniCamera::StopRecording() {
  if (!impl_ || !impl_->recorder_.isValid()) return;
  impl_->recorder_.stop();
  impl_->recorder_.destroy();
}

void OpenniCamera::Close() {
  if (!impl_) return;
  StopRecording();
  Impl& d = *impl_;
  if (d.listeners_added_) {
    d.color_.removeNewFrameListener(&d.color_listener_);
    d.depth_.removeNewFrameListener(&d.depth_listener_);
    openni::OpenNI::removeDeviceDisconnectedListener(&d);
    openni::OpenNI::removeDeviceStateChangedListener(&d);
    d.listeners_added_ = false;
  }
  ParkRecordingPlayer();
  Stop();
  d.color_.destroy();
  d.depth_.destroy();
  d.device_.close();
  impl_.reset();
}

void OpenniCamera::ParkRecordingPlayer() {
  // OpenNI's file driver walks its list of streams on its player thread without its lock (every
  // 10 ms while no stream runs, continuously at the end of a recording played once), and OpenNI
  // destroys the driver's streams when the device closes, before it stops that thread: on a
  // loaded machine the thread then reads a freed stream and the process crashes. In manual
  // playback, with a stream still running and repetition on, the thread waits in the next
  // frame's delivery for a trigger (up to 2 s; no listener reads frames any more, so none comes)
  // and touches no stream there; closing the device wakes it and ends it. A recording played
  // once to its end cannot be parked (the driver neither rewinds nor seeks there), so closing it
  // stays exposed to the driver's race.
  if (!started_ || !impl_->device_.isFile()) return;
  openni::PlaybackControl* playback = impl_->device_.getPlaybackControl();
  if (playback == nullptr) return;
  playback->setRepeatEnabled(true);
  playback->setSpeed(-1.0f);
  std::this_thread::sleep_for(std::chrono::milliseconds(100));
}

bool OpenniCamera::is_open() const { return impl_ != nullptr; }

Time OpenniCamera::last_frame_time() const {
  if (!impl_) return Time();
  std::lock_guard<std::mutex> lock(impl_->mutex_);
  return impl_->last_frame_;
}

double OpenniCamera::seconds_without_frames() const {
  if (!impl_ || !started_) return 0.0;
  std::lock_guard<std::mutex> lock(impl_->mutex_);
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - impl_->last_activity_).count();
}

size_t OpenniCamera::pairs() const {
  if (!impl_) return 0;
  std::lock_guard<std::mutex> lock(impl_->mutex_);
  return impl_->pairer_.pairs();
}

size_t OpenniCamera::dropped() const {
  if (!impl_) return 0;
  std::lock_guard<std::mutex> lock(impl_->mutex_);
  return impl_->pairer_.dropped();
}

double OpenniCamera::frame_cpu_ms() const {
  if (!impl_) return 0.0;
  std::lock_guard<std::mutex> lock(impl_->mutex_);
  return impl_->cpu_ms_;
}

CameraIntrinsics OpenniCamera::FieldOfViewIntrinsics() const {
  if (!impl_) return CameraIntrinsics();
  const openni::VideoMode mode = impl_->color_.getVideoMode();
  return IntrinsicsFromFieldOfView(mode.getResolutionX(), mode.getResolutionY(),
                                   impl_->color_.getHorizontalFieldOfView(),
                                   impl_->color_.getVerticalFieldOfView());
}

std::string OpenniCamera::description() const {
  if (!impl_) return "closed";
  const openni::VideoMode mode = impl_->color_.getVideoMode();
  std::ostringstream s;
  s << impl_->name_ << " (" << impl_->uri_ << "), " << mode.getResolutionX() << "x"
    << mode.getResolutionY() << " @ " << mode.getFps() << " Hz, hardware registration "
    << (hardware_registration_ ? "on" : "off (depth unregistered)");
  return s.str();
}

}  // namespace icgm
