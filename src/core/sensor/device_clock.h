// Maps a sensor's own clock (microseconds since the device started, as OpenNI stamps frames) to
// host time, compensating the offset between the clocks and their relative drift.
//
// Each frame gives one sample: its device stamp d and the host time h at which it arrived.
// h - d is the clock offset plus the transfer latency, which is never negative, so the capture
// instant lies on the lower envelope of the samples. The estimate is the line under the
// samples of the last `window_s` that lies closest to them on average (Moon, Skelly, Towsley
// 1999: the edge of the samples' lower convex hull spanning their mean device time). Only
// samples confirmed by others count: at least `min_support` samples within `bin_s` of device
// time lie within `support_tolerance_s` of each other. A lone sample far below the rest (the
// host clock read stale, as ROS simulated time delivered late) does not pull the line down.
// The drift is estimated once the samples span `bin_s`, and is clamped to `max_drift_ppm`.
//
// The mapping handed out is a separate line that follows the device clock: from one mapped
// frame to the next it advances by the device interval scaled by the drift, and moves towards
// the estimate by at most `max_slew` of that interval. Mapped stamps therefore rise strictly
// with the device stamps and keep their spacing within `max_slew`, whatever the arrivals do:
// a backlog at start-up (every early frame late by up to seconds) is worked off gradually
// instead of by a step back in time. Until then a mapped stamp may lie after its arrival.
//
// Device stamps that step back by less than `reset_jump_s` are frames of another stream read
// out of order (each OpenNI stream delivers on its own thread): they are samples like any
// other and are mapped on the current line. A device clock that runs back further, or leaps
// forward by more than `reset_jump_s` beyond the host time that passed (device re-opened,
// timestamps reset), restarts the estimate.
#pragma once

#include <cstdint>
#include <deque>

#include "core/common/status.h"
#include "core/common/time.h"

namespace icgm {

struct DeviceClockOptions {
  double window_s = 20.0;         // samples kept for the drift fit
  double bin_s = 1.0;             // samples must span this before the drift is estimated
  double max_drift_ppm = 1000.0;  // crystals drift by tens of ppm; more is a fit artefact
  double reset_jump_s = 1.0;      // a jump of the device clock beyond this restarts the estimate
  double max_slew = 0.25;         // mapped intervals within this fraction of the device's
  double support_tolerance_s = 0.005;  // samples this close to each other confirm each other
  int min_support = 3;                 // samples (itself included) that confirm a sample

  Status Validate() const;
};

class DeviceClock {
 public:
  explicit DeviceClock(const DeviceClockOptions& options = DeviceClockOptions());

  // Adds the sample (device_us, arrival) and returns the host time of the capture device_us.
  Time Map(uint64_t device_us, Time arrival);
  // Host time of device_us on the current mapping, without adding a sample (valid after the
  // first Map).
  Time ToHost(uint64_t device_us) const;
  const DeviceClockOptions& options() const { return options_; }

  double drift_ppm() const { return drift_ * 1e6; }
  int resets() const { return resets_; }
  size_t samples() const { return samples_.size(); }

 private:
  struct Sample {
    double device_s;  // since device0_us_
    double offset_s;  // arrival - device, relative to host0_
    int support = 1;  // samples (itself included) within bin_s / 2 and support_tolerance_s
  };
  // Counts the new sample at `index` in its neighbours' support and theirs in its own (add 1),
  // or removes it from theirs (add -1).
  void CountSupport(size_t index, int add);
  void Reset(uint64_t device_us, Time arrival);
  void AddSample(double device_s, double offset_s);
  void Fit();
  double EstimateAt(double device_s) const { return device_s + offset_ + drift_ * device_s; }
  double DeviceSeconds(uint64_t device_us) const;

  DeviceClockOptions options_;
  bool started_ = false;
  uint64_t device0_us_ = 0;
  uint64_t last_device_us_ = 0;  // the latest device stamp seen
  Time last_arrival_;            // the arrival of last_device_us_
  Time host0_;
  std::deque<Sample> samples_;  // sorted by device time
  double drift_ = 0.0;          // estimate: d(offset)/d(device time)
  double offset_ = 0.0;         // estimate: offset at device time 0 (s)
  // The mapping: host time (relative to host0_) of the device time anchor_device_s_, and its
  // rate beyond it.
  double anchor_device_s_ = 0.0;
  double anchor_host_s_ = 0.0;
  double map_drift_ = 0.0;
  int resets_ = 0;
};

}  // namespace icgm
