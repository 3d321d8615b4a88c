// Maps a sensor's own clock (microseconds since the device started, as OpenNI stamps frames) to
// host time, compensating the offset between the clocks and their relative drift.
//
// Each frame gives one sample: its device stamp d and the host time h at which it arrived.
// h - d is the clock offset plus the transfer latency, which is never negative, so the capture
// instant lies on the lower envelope of the samples. Offset and drift are the line under all
// samples of the last `window_s` that lies closest to them on average (Moon, Skelly, Towsley
// 1999: the edge of the samples' lower convex hull spanning their mean device time), so a
// mapped stamp never lies after its arrival. The drift is estimated once the samples span
// `bin_s`, and is clamped to `max_drift_ppm`. A device clock that runs backwards, or leaps forward so that a capture would be
// mapped more than `reset_jump_s` after its arrival (device re-opened, timestamps reset),
// restarts the estimate.
#pragma once

#include <cstdint>
#include <deque>

#include "core/common/status.h"
#include "core/common/time.h"

namespace icgm {

struct DeviceClockOptions {
  double window_s = 20.0;        // samples kept for the drift fit
  double bin_s = 1.0;            // samples must span this before the drift is estimated
  double max_drift_ppm = 1000.0; // crystals drift by tens of ppm; more is a fit artefact
  double reset_jump_s = 1.0;     // a jump of the offset beyond this restarts the estimate

  Status Validate() const;
};

class DeviceClock {
 public:
  explicit DeviceClock(const DeviceClockOptions& options = DeviceClockOptions());

  // Adds the sample (device_us, arrival) and returns the host time of the capture device_us.
  Time Map(uint64_t device_us, Time arrival);
  // Host time of device_us with the current estimate, without adding a sample (valid after the
  // first Map).
  Time ToHost(uint64_t device_us) const;

  double drift_ppm() const { return drift_ * 1e6; }
  int resets() const { return resets_; }
  size_t samples() const { return samples_.size(); }

 private:
  struct Sample {
    double device_s;  // since device0_us_
    double offset_s;  // arrival - device, relative to host0_
  };
  void Reset(uint64_t device_us, Time arrival);
  void Fit();

  DeviceClockOptions options_;
  bool started_ = false;
  uint64_t device0_us_ = 0;
  uint64_t last_device_us_ = 0;
  Time host0_;
  std::deque<Sample> samples_;
  double drift_ = 0.0;   // d(offset)/d(device time)
  double offset_ = 0.0;  // offset at device time 0 (s)
  int resets_ = 0;
};

}  // namespace icgm
