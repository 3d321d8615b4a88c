// Building blocks of the project's OpenNI2 driver modules (OniDriverAPI): a device with one
// RGB888 colour stream and one DEPTH_1_MM depth stream, each in a single fixed video mode, and
// OpenNI's image-registration property. The virtual device (virtual_driver.cpp) and the Kinect
// v1 driver on libfreenect (freenect_driver.cpp) derive from these and add only where their
// frames come from and which registration modes they offer.
//
// Header-only: each driver module is its own shared library that OpenNI2 loads from its drivers
// folder; include it only there (it needs the driver API's allocation macros defined first).
#pragma once

#include <atomic>
#include <cmath>
#include <cstring>
#include <mutex>

#define XN_NEW(type, arg) new type(arg)
#define XN_DELETE(p) delete (p)
#include <Driver/OniDriverAPI.h>

namespace icgm::oni_driver {

// Copies a property value into OpenNI's buffer of *size bytes.
template <typename T>
OniStatus PutProperty(const T& value, void* data, int* size) {
  if (*size < static_cast<int>(sizeof(T))) return ONI_STATUS_BAD_PARAMETER;
  std::memcpy(data, &value, sizeof(T));
  *size = sizeof(T);
  return ONI_STATUS_OK;
}

// The one video mode of a stream: RGB888 colour or 1 mm depth.
inline OniVideoMode RgbdVideoMode(OniSensorType type, int width_px, int height_px, int fps) {
  OniVideoMode m{};
  m.pixelFormat = type == ONI_SENSOR_COLOR ? ONI_PIXEL_FORMAT_RGB888 : ONI_PIXEL_FORMAT_DEPTH_1_MM;
  m.resolutionX = width_px;
  m.resolutionY = height_px;
  m.fps = fps;
  return m;
}

// A colour or depth stream in one fixed mode, not mirrored, not cropped. Its fields of view
// follow focal_px(), which a driver overrides when the focal length depends on device state.
class RgbdStream : public oni::driver::StreamBase {
 public:
  RgbdStream(OniSensorType type, const OniVideoMode& mode, double fx_px, double fy_px,
             int max_depth_mm)
      : type_(type), mode_(mode), fx_px_(fx_px), fy_px_(fy_px), max_depth_mm_(max_depth_mm) {}

  OniStatus start() override {
    running_ = true;
    return ONI_STATUS_OK;
  }
  void stop() override { running_ = false; }
  bool running() const { return running_; }
  int bytes_per_pixel() const { return type_ == ONI_SENSOR_COLOR ? 3 : 2; }
  int row_bytes() const { return mode_.resolutionX * bytes_per_pixel(); }

  OniBool isPropertySupported(int id) override {
    return id == ONI_STREAM_PROPERTY_VIDEO_MODE || id == ONI_STREAM_PROPERTY_HORIZONTAL_FOV ||
           id == ONI_STREAM_PROPERTY_VERTICAL_FOV || id == ONI_STREAM_PROPERTY_MAX_VALUE ||
           id == ONI_STREAM_PROPERTY_MIN_VALUE || id == ONI_STREAM_PROPERTY_STRIDE ||
           id == ONI_STREAM_PROPERTY_MIRRORING || id == ONI_STREAM_PROPERTY_CROPPING;
  }
  OniStatus getProperty(int id, void* data, int* size) override {
    switch (id) {
      case ONI_STREAM_PROPERTY_VIDEO_MODE:
        return PutProperty(mode_, data, size);
      case ONI_STREAM_PROPERTY_HORIZONTAL_FOV:
        return PutProperty(
            static_cast<float>(2.0 * std::atan(0.5 * mode_.resolutionX / focal_px(true))), data,
            size);
      case ONI_STREAM_PROPERTY_VERTICAL_FOV:
        return PutProperty(
            static_cast<float>(2.0 * std::atan(0.5 * mode_.resolutionY / focal_px(false))), data,
            size);
      case ONI_STREAM_PROPERTY_MAX_VALUE:
        return PutProperty(type_ == ONI_SENSOR_COLOR ? 255 : max_depth_mm_, data, size);
      case ONI_STREAM_PROPERTY_MIN_VALUE:
        return PutProperty(0, data, size);
      case ONI_STREAM_PROPERTY_STRIDE:
        return PutProperty(row_bytes(), data, size);
      case ONI_STREAM_PROPERTY_MIRRORING:
        return PutProperty(static_cast<OniBool>(FALSE), data, size);
      // OpenNI's Recorder writes the cropping state only for a stream that reports one, and its
      // file player drops every frame of a stream whose recording has none: report "off".
      case ONI_STREAM_PROPERTY_CROPPING: {
        OniCropping cropping{};
        cropping.enabled = FALSE;
        cropping.width = mode_.resolutionX;
        cropping.height = mode_.resolutionY;
        return PutProperty(cropping, data, size);
      }
      default:
        return ONI_STATUS_NOT_SUPPORTED;
    }
  }
  // Accepts only what the stream already is: its mode, no mirroring, no cropping.
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
      return static_cast<const OniCropping*>(data)->enabled ? ONI_STATUS_NOT_SUPPORTED
                                                            : ONI_STATUS_OK;
    }
    return ONI_STATUS_NOT_SUPPORTED;
  }
  int getRequiredFrameSize() override { return row_bytes() * mode_.resolutionY; }

  // Sends one frame stamped device_us (the device clock, µs) while the stream runs:
  // fill(void* data) writes the image, rows of row_bytes() without padding.
  template <typename Fill>
  void Send(Fill&& fill, uint64_t device_us, int index) {
    if (!running_) return;
    OniFrame* frame = getServices().acquireFrame();
    if (frame == nullptr) return;
    fill(frame->data);
    frame->dataSize = getRequiredFrameSize();
    frame->sensorType = type_;
    frame->timestamp = device_us;
    frame->frameIndex = index;
    frame->width = mode_.resolutionX;
    frame->height = mode_.resolutionY;
    frame->videoMode = mode_;
    frame->croppingEnabled = FALSE;
    frame->cropOriginX = 0;
    frame->cropOriginY = 0;
    frame->stride = row_bytes();
    raiseNewFrame(frame);
    getServices().releaseFrame(frame);
  }

 protected:
  // Focal length (pixels) behind the horizontal (or vertical) field of view.
  virtual double focal_px(bool horizontal) const { return horizontal ? fx_px_ : fy_px_; }
  OniSensorType type() const { return type_; }

 private:
  const OniSensorType type_;
  const OniVideoMode mode_;
  const double fx_px_, fy_px_;
  const int max_depth_mm_;
  std::atomic<bool> running_{false};
};

// A device with one colour and one depth stream (each created at most once at a time) and
// OpenNI's image-registration property. Stream is RgbdStream or a class derived from it;
// a driver makes its streams in NewStream and says which registration modes it accepts.
template <typename Stream>
class RgbdDevice : public oni::driver::DeviceBase {
 public:
  RgbdDevice(int width_px, int height_px, int fps, OniImageRegistrationMode registration)
      : registration_(registration) {
    modes_[0] = RgbdVideoMode(ONI_SENSOR_COLOR, width_px, height_px, fps);
    modes_[1] = RgbdVideoMode(ONI_SENSOR_DEPTH, width_px, height_px, fps);
    sensors_[0] = {ONI_SENSOR_COLOR, 1, &modes_[0]};
    sensors_[1] = {ONI_SENSOR_DEPTH, 1, &modes_[1]};
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
    slot = NewStream(type, modes_[type == ONI_SENSOR_COLOR ? 0 : 1]);
    return slot;
  }
  void destroyStream(oni::driver::StreamBase* stream) override {
    std::lock_guard<std::mutex> lock(mutex_);
    if (stream == color_) color_ = nullptr;
    if (stream == depth_) depth_ = nullptr;
    delete stream;
  }
  OniBool isImageRegistrationModeSupported(OniImageRegistrationMode mode) override {
    return RegistrationOffered(mode);
  }
  OniBool isPropertySupported(int id) override {
    return id == ONI_DEVICE_PROPERTY_IMAGE_REGISTRATION;
  }
  OniStatus getProperty(int id, void* data, int* size) override {
    if (id != ONI_DEVICE_PROPERTY_IMAGE_REGISTRATION) return ONI_STATUS_NOT_SUPPORTED;
    return PutProperty(registration_.load(), data, size);
  }
  OniStatus setProperty(int id, const void* data, int size) override {
    if (id != ONI_DEVICE_PROPERTY_IMAGE_REGISTRATION || size != sizeof(OniImageRegistrationMode)) {
      return ONI_STATUS_NOT_SUPPORTED;
    }
    const OniImageRegistrationMode mode = *static_cast<const OniImageRegistrationMode*>(data);
    if (!RegistrationOffered(mode)) return ONI_STATUS_NOT_SUPPORTED;
    registration_ = mode;
    return ONI_STATUS_OK;
  }

 protected:
  // The stream of `type` in `mode` (owned by OpenNI until destroyStream).
  virtual Stream* NewStream(OniSensorType type, const OniVideoMode& mode) = 0;
  virtual bool RegistrationOffered(OniImageRegistrationMode mode) const = 0;

  bool registered() const { return registration_ != ONI_IMAGE_REGISTRATION_OFF; }
  const std::atomic<OniImageRegistrationMode>& registration() const { return registration_; }
  // Colour or depth stream, null when not created; under mutex_.
  Stream* stream(bool color) const { return color ? color_ : depth_; }
  bool AnyRunning() {
    std::lock_guard<std::mutex> lock(mutex_);
    return (color_ != nullptr && color_->running()) || (depth_ != nullptr && depth_->running());
  }

  std::mutex mutex_;  // guards the stream slots

 private:
  OniVideoMode modes_[2];
  OniSensorInfo sensors_[2];
  Stream* color_ = nullptr;
  Stream* depth_ = nullptr;
  std::atomic<OniImageRegistrationMode> registration_;
};

}  // namespace icgm::oni_driver
