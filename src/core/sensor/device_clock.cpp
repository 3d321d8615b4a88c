#include "core/sensor/device_clock.h"

#include <algorithm>
#include <cmath>
#include <iterator>
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
  // The mapping must keep rising: the slew stays below the device interval minus the drift.
  if (!(max_slew > 0.0 && max_slew <= 0.5)) {
    return Status::Error("device clock: max_slew not in (0, 0.5]");
  }
  if (!(support_tolerance_s > 0.0 && support_tolerance_s <= 1.0)) {
    return Status::Error("device clock: support_tolerance_s not in (0, 1]");
  }
  if (min_support < 1 || min_support > 100) {
    return Status::Error("device clock: min_support not in [1, 100]");
  }
  return Status::Ok();
}

DeviceClock::DeviceClock(const DeviceClockOptions& options) : options_(options) {}

void DeviceClock::Reset(uint64_t device_us, Time arrival) {
  if (started_) ++resets_;
  started_ = true;
  device0_us_ = device_us;
  last_device_us_ = device_us;
  last_arrival_ = arrival;
  host0_ = arrival;
  samples_.clear();
  drift_ = 0.0;
  offset_ = 0.0;
  anchor_device_s_ = 0.0;
  anchor_host_s_ = 0.0;
  map_drift_ = 0.0;
}

double DeviceClock::DeviceSeconds(uint64_t device_us) const {
  return (static_cast<double>(device_us) - static_cast<double>(device0_us_)) * 1e-6;
}

Time DeviceClock::ToHost(uint64_t device_us) const {
  const double d = DeviceSeconds(device_us);
  const double h = anchor_host_s_ + (d - anchor_device_s_) * (1.0 + map_drift_);
  return Time::FromNanoseconds(host0_.nanoseconds() + static_cast<int64_t>(std::llround(h * 1e9)));
}

Time DeviceClock::Map(uint64_t device_us, Time arrival) {
  // A device clock that ran back further than streams read out of order explain, or advanced
  // beyond the host time that passed by more than the jump bound, was restarted. A late arrival
  // (a stall, a backlog) leaves the lower envelope where it is.
  bool reset = !started_;
  if (started_) {
    const double back_s = device_us < last_device_us_ ? (last_device_us_ - device_us) * 1e-6 : 0.0;
    const double ahead_s = device_us > last_device_us_ ? (device_us - last_device_us_) * 1e-6 -
                                                             DurationSeconds(arrival, last_arrival_)
                                                       : 0.0;
    reset = back_s > options_.reset_jump_s || ahead_s > options_.reset_jump_s;
  }
  if (reset) Reset(device_us, arrival);
  const double d = DeviceSeconds(device_us);
  AddSample(d, DurationSeconds(arrival, host0_) - d);
  Fit();
  if (reset) {
    anchor_device_s_ = d;
    anchor_host_s_ = EstimateAt(d);
    map_drift_ = drift_;
  } else if (device_us > last_device_us_) {
    // Advance along the device clock, turning towards the estimate at a bounded rate.
    const double step_s = d - anchor_device_s_;
    const double predicted = anchor_host_s_ + step_s * (1.0 + map_drift_);
    const double max_turn = options_.max_slew * step_s;
    anchor_host_s_ = predicted + std::clamp(EstimateAt(d) - predicted, -max_turn, max_turn);
    anchor_device_s_ = d;
    map_drift_ = drift_;
  }
  // A frame older than the latest (another stream's, read late) is mapped on the current line.
  if (device_us > last_device_us_) {
    last_device_us_ = device_us;
    last_arrival_ = arrival;
  }
  return ToHost(device_us);
}

void DeviceClock::AddSample(double device_s, double offset_s) {
  // Kept sorted by device time; a frame read out of order goes in its place.
  auto it = samples_.end();
  while (it != samples_.begin() && std::prev(it)->device_s > device_s) --it;
  it = samples_.insert(it, {device_s, offset_s});
  CountSupport(static_cast<size_t>(it - samples_.begin()), 1);
  const double newest = samples_.back().device_s;
  while (!samples_.empty() && newest - samples_.front().device_s > options_.window_s) {
    CountSupport(0, -1);
    samples_.pop_front();
  }
}

void DeviceClock::CountSupport(size_t index, int add) {
  const double half_bin = 0.5 * options_.bin_s;
  Sample& s = samples_[index];
  auto count = [&](Sample& other) {
    if (std::fabs(other.offset_s - s.offset_s) > options_.support_tolerance_s) return;
    other.support += add;
    if (add > 0) s.support += add;
  };
  for (size_t j = index; j-- > 0 && samples_[j].device_s >= s.device_s - half_bin;)
    count(samples_[j]);
  for (size_t j = index + 1; j < samples_.size() && samples_[j].device_s <= s.device_s + half_bin;
       ++j) {
    count(samples_[j]);
  }
}

void DeviceClock::Fit() {
  // The samples confirmed by at least min_support samples (itself included) within bin_s / 2 of
  // device time and support_tolerance_s of offset; all of them while none is.
  std::vector<Sample> used;
  used.reserve(samples_.size());
  for (const Sample& s : samples_) {
    if (s.support >= options_.min_support) used.push_back(s);
  }
  if (used.empty()) used.assign(samples_.begin(), samples_.end());

  // Lower convex hull of the samples (sorted by device time; Andrew's monotone chain).
  std::vector<Sample> hull;
  for (const Sample& s : used) {
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
  for (const Sample& s : used) mean_d += s.device_s;
  mean_d /= static_cast<double>(used.size());
  double slope = 0.0;
  if (hull.size() >= 2 && used.back().device_s - used.front().device_s >= options_.bin_s) {
    size_t i = 1;
    while (i + 1 < hull.size() && hull[i].device_s < mean_d) ++i;
    const Sample& a = hull[i - 1];
    const Sample& b = hull[i];
    if (b.device_s > a.device_s) slope = (b.offset_s - a.offset_s) / (b.device_s - a.device_s);
  }
  const double max_drift = options_.max_drift_ppm * 1e-6;
  drift_ = std::clamp(slope, -max_drift, max_drift);
  // Lower the line onto the lowest sample: no capture is estimated after its arrival.
  double offset = std::numeric_limits<double>::infinity();
  for (const Sample& s : hull) offset = std::min(offset, s.offset_s - drift_ * s.device_s);
  offset_ = offset;
}

}  // namespace icgm
