#include "core/sensor/device_clock.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

namespace icgm {

Status DeviceClockOptions::Validate() const {
  if (!(bin_s > 0.0) || !(window_s >= 2.0 * bin_s)) {
    return Status::Error("device clock: need bin_s > 0 and window_s >= 2 bin_s");
  }
  if (!(max_drift_ppm >= 0.0 && max_drift_ppm <= 1e5)) {
    return Status::Error("device clock: max_drift_ppm not in [0, 100000]");
  }
  if (!(reset_jump_s > 0.0)) return Status::Error("device clock: reset_jump_s must be > 0");
  return Status::Ok();
}

DeviceClock::DeviceClock(const DeviceClockOptions& options) : options_(options) {}

void DeviceClock::Reset(uint64_t device_us, Time arrival) {
  if (started_) ++resets_;
  started_ = true;
  device0_us_ = device_us;
  host0_ = arrival;
  samples_.clear();
  drift_ = 0.0;
  offset_ = 0.0;
}

Time DeviceClock::ToHost(uint64_t device_us) const {
  const double d = (static_cast<double>(device_us) - static_cast<double>(device0_us_)) * 1e-6;
  const double h = d + offset_ + drift_ * d;
  return Time::FromNanoseconds(host0_.nanoseconds() + static_cast<int64_t>(std::llround(h * 1e9)));
}

Time DeviceClock::Map(uint64_t device_us, Time arrival) {
  // A clock running backwards, or a capture mapped after its arrival by more than the jump
  // bound (the device clock leapt forward), restarts the estimate. A late arrival (a stall)
  // leaves the lower envelope where it is.
  if (!started_ || device_us < last_device_us_ ||
      DurationSeconds(ToHost(device_us), arrival) > options_.reset_jump_s) {
    Reset(device_us, arrival);
  }
  last_device_us_ = device_us;
  const double d = (static_cast<double>(device_us) - static_cast<double>(device0_us_)) * 1e-6;
  samples_.push_back({d, DurationSeconds(arrival, host0_) - d});
  while (!samples_.empty() && d - samples_.front().device_s > options_.window_s) {
    samples_.pop_front();
  }
  Fit();
  return ToHost(device_us);
}

void DeviceClock::Fit() {
  // Lower convex hull of the samples (sorted by device time; Andrew's monotone chain).
  std::vector<Sample> hull;
  for (const Sample& s : samples_) {
    while (hull.size() >= 2) {
      const Sample& a = hull[hull.size() - 2];
      const Sample& b = hull.back();
      const double cross = (b.device_s - a.device_s) * (s.offset_s - a.offset_s) -
                           (b.offset_s - a.offset_s) * (s.device_s - a.device_s);
      if (cross > 0.0) break;  // a-b-s turns left: b stays on the lower hull
      hull.pop_back();
    }
    hull.push_back(s);
  }
  // The line under every sample that is closest to them on average (the linear programme of
  // Moon et al. 1999) is the hull edge spanning the mean device time.
  double mean_d = 0.0;
  for (const Sample& s : samples_) mean_d += s.device_s;
  mean_d /= static_cast<double>(samples_.size());
  double slope = 0.0;
  if (hull.size() >= 2 && samples_.back().device_s - samples_.front().device_s >= options_.bin_s) {
    size_t i = 1;
    while (i + 1 < hull.size() && hull[i].device_s < mean_d) ++i;
    const Sample& a = hull[i - 1];
    const Sample& b = hull[i];
    if (b.device_s > a.device_s) slope = (b.offset_s - a.offset_s) / (b.device_s - a.device_s);
  }
  const double max_drift = options_.max_drift_ppm * 1e-6;
  drift_ = std::clamp(slope, -max_drift, max_drift);
  // Lower the line onto the lowest sample: no capture is mapped after its arrival.
  double offset = std::numeric_limits<double>::infinity();
  for (const Sample& s : hull) offset = std::min(offset, s.offset_s - drift_ * s.device_s);
  offset_ = offset;
}

}  // namespace icgm
