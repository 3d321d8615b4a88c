// Time-indexed buffer of wheel odometry poses T_odom_base, the fallback motion source of the
// hybrid SLAM (thesis ch. 6.1.1.1: "when failed, based on time relationship between tires'
// odometry information and depth and RGB-vision information, we update relative pose which
// calculated from tires' odometry to R").
//
// Wheel odometry is not trusted blindly. Add() refuses samples whose stamp does not increase
// (time going backwards / duplicates) and flags a jump when the motion since the previous sample
// implies a speed above max_speed_mps or a yaw rate above max_yaw_rate_dps (e.g. an odometry
// reset); the sample is stored, but no relative motion is reported across it. RelativeMotion()
// fails, with the reason, across a jump, across a gap between samples longer than max_gap_s, or
// outside the buffered time span (beyond a small extrapolation allowance).
// Poses between samples are interpolated (lerp + slerp, pose.h Interpolate).
#pragma once

#include <cstddef>
#include <deque>

#include "core/common/pose.h"
#include "core/common/status.h"
#include "core/common/time.h"

namespace icgm {

class OptionReader;

struct WheelOdometryOptions {
  double max_gap_s = 0.5;
  double max_speed_mps = 3.0;
  double max_yaw_rate_dps = 360.0;
  // Queries up to this far beyond the newest sample are extrapolated at the last velocity.
  double max_extrapolation_s = 0.05;
  // Older samples are dropped beyond this many.
  int max_samples = 20000;
};

// Fills `options` from a `wheel_odometry:` section; throws LoadError on bad values.
void ReadOptions(const OptionReader& reader, WheelOdometryOptions* options);

class WheelOdometryBuffer {
 public:
  explicit WheelOdometryBuffer(const WheelOdometryOptions& options = WheelOdometryOptions());

  // Stores T_odom_base at `stamp`. Returns an error (sample dropped) when the stamp is not after
  // the newest one or the pose is not finite; an error (sample kept, marked as a jump) when the
  // implied speed or yaw rate exceeds the limits.
  Status Add(Time stamp, const Pose3& odom_base);

  // T_odom_base at `t` by interpolation.
  Status PoseAt(Time t, Pose3* odom_base) const;

  // Motion of the base from `from` to `to`: T_base(from)_base(to) = PoseAt(from)^-1 PoseAt(to).
  Status RelativeMotion(Time from, Time to, Pose3* base_from_to) const;

  size_t size() const { return samples_.size(); }
  bool empty() const { return samples_.empty(); }
  Time oldest() const { return samples_.empty() ? Time() : samples_.front().stamp; }
  Time newest() const { return samples_.empty() ? Time() : samples_.back().stamp; }
  size_t jumps_detected() const { return jumps_; }
  size_t rejected_samples() const { return rejected_; }
  // Drops samples older than `t` (keeps one at or before t for interpolation).
  void TrimBefore(Time t);
  void Clear() { samples_.clear(); }

 private:
  struct Sample {
    Time stamp;
    Pose3 pose;
    bool jump_before = false;  // the segment from the previous sample is not trustworthy
  };
  // Index of the last sample with stamp <= t, or -1.
  long FloorIndex(Time t) const;

  WheelOdometryOptions options_;
  std::deque<Sample> samples_;
  size_t jumps_ = 0;
  size_t rejected_ = 0;
};

}  // namespace icgm
