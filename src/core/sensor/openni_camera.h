// An OpenNI2 RGB-D device (Kinect, Xtion, an .oni recording, or the project's virtual device)
// delivering depth-colour pairs: colour as CV_8UC3 BGR, depth as CV_16UC1 millimetres registered
// to the colour camera when the device offers hardware registration, both stamped with the
// device clock mapped to host time (DeviceClock) and paired by FramePairer.
//
// Open() opens the device and creates the streams; Start()/Stop() run them (a driver publishes
// lazily by starting only while someone listens). Failures are Status values with a reason
// ("no OpenNI2 device connected", "cannot open 'x.oni': ..."). Frames arrive on OpenNI's thread.
#pragma once

#include <atomic>
#include <functional>
#include <memory>
#include <mutex>
#include <string>

#include "core/common/camera.h"
#include "core/common/status.h"
#include "core/common/time.h"
#include "core/sensor/device_clock.h"
#include "core/sensor/frame_pairer.h"

namespace icgm {

struct OpenniCameraOptions {
  // "" = the first device; a path ending in .oni plays a recording (which must exist, unless
  // wait_for_recording)
  std::string uri;
  // A recording path that does not exist yet (a recording still being written or copied) is
  // waited for: opened once it appears, retried like a device. false: refused up front.
  bool wait_for_recording = false;
  int width_px = 640;
  int height_px = 480;
  int fps = 30;
  bool hardware_registration = true;  // depth registered to colour when offered
  bool hardware_sync = true;          // the device's depth-colour frame sync when offered
  double max_sync_dt_s = 0.02;  // colour and depth further apart are not paired (as TUM associates)
  // An .oni recording starts again at its end (OpenNI's default), else it plays once.
  bool oni_repeat = true;
  // An .oni recording does not say whether its depth was registered to colour (OpenNI's Recorder
  // keeps no device state): taken as registered (recorded from a registered device) unless false.
  bool oni_registered = true;
  DeviceClockOptions clock;

  Status Validate() const;
};

class OpenniCamera {
 public:
  using PairCallback = std::function<void(const RgbdPair&)>;
  using HostClock = std::function<Time()>;

  OpenniCamera();
  ~OpenniCamera();
  OpenniCamera(const OpenniCamera&) = delete;
  OpenniCamera& operator=(const OpenniCamera&) = delete;

  // Initialises OpenNI (once per process), opens the device and creates colour and depth
  // streams in the requested mode. `clock` gives the host time of a frame's arrival.
  Status Open(const OpenniCameraOptions& options, HostClock clock, PairCallback callback);
  Status Start();
  void Stop();
  void Close();

  // Records both streams, as the device delivers them, to an OpenNI .oni file (lossless; play
  // it back by opening the file's path) until StopRecording or Close.
  Status StartRecording(const std::string& oni_path);
  void StopRecording();

  bool is_open() const;
  bool is_started() const { return started_; }
  // The device was unplugged since Open (OpenNI's disconnection event).
  bool disconnected() const { return disconnected_; }
  // The recording the device plays (a fakenect dump through the Kinect v1 driver, an .oni file
  // played once) has ended: OpenNI's end-of-file device state since Open, and how often it came
  // (a driver says it once).
  bool end_of_recording() const { return recording_ends_ > 0; }
  int recording_ends() const { return recording_ends_; }
  // Host time of the last frame received (zero before any).
  Time last_frame_time() const;
  // Wall-clock seconds since the last frame arrived or, before any since Start, since Start (0
  // when not started): a device that stopped delivering shows here.
  double seconds_without_frames() const;
  // Pinhole intrinsics of the colour stream from its field of view (no distortion), for a
  // device without a camera YAML; depth_scale 1000 (mm).
  CameraIntrinsics FieldOfViewIntrinsics() const;
  bool hardware_registration() const { return hardware_registration_; }
  // "PrimeSense Carmine 1.09 (uri), 640x480 @ 30 Hz, hardware registration on"
  std::string description() const;
  size_t pairs() const;
  size_t dropped() const;
  // CPU time (of the threads that ran it) spent turning OpenNI frames into stamped, paired
  // images since Open, excluding the pair callback (ms).
  double frame_cpu_ms() const;

 private:
  // Before the streams of a played recording are destroyed: holds OpenNI's file player where it
  // touches no stream (see the definition).
  void ParkRecordingPlayer();

  class Impl;
  std::unique_ptr<Impl> impl_;
  std::atomic<bool> started_{false};
  std::atomic<bool> disconnected_{false};
  std::atomic<int> recording_ends_{0};
  bool hardware_registration_ = false;
};

// Pinhole intrinsics of a width x height image whose horizontal and vertical fields of view are
// hfov_rad and vfov_rad (principal point at the centre).
CameraIntrinsics IntrinsicsFromFieldOfView(int width_px, int height_px, double hfov_rad,
                                           double vfov_rad);

}  // namespace icgm
