#include "core/odometry/wheel_odometry_buffer.h"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "core/common/option_reader.h"

namespace icgm {

void ReadOptions(const OptionReader& reader, WheelOdometryOptions* options) {
  reader.Read("max_gap_s", &options->max_gap_s, 1e-3, 3600.0);
  reader.Read("max_speed_mps", &options->max_speed_mps, 1e-3, 1000.0);
  reader.Read("max_yaw_rate_dps", &options->max_yaw_rate_dps, 1e-3, 100000.0);
  reader.Read("max_extrapolation_s", &options->max_extrapolation_s, 0.0, 10.0);
  reader.Read("max_samples", &options->max_samples, 2, 100000000);
}

WheelOdometryBuffer::WheelOdometryBuffer(const WheelOdometryOptions& options) : options_(options) {}

namespace {
// Yaw of the relative rotation about the base's z axis (planar robot), in radians.
double YawRad(const Pose3& rel) {
  const Eigen::Matrix3d& r = rel.linear();
  return std::atan2(r(1, 0), r(0, 0));
}
}  // namespace

Status WheelOdometryBuffer::Add(Time stamp, const Pose3& odom_base) {
  if (!odom_base.matrix().allFinite()) {
    ++rejected_;
    return Status::Error("wheel odometry sample at " + stamp.ToString() + " is not finite");
  }
  Sample s{stamp, odom_base, false};
  Status status = Status::Ok();
  if (!samples_.empty()) {
    const Sample& last = samples_.back();
    if (stamp <= last.stamp) {
      ++rejected_;
      std::ostringstream m;
      m << "wheel odometry time went backwards: " << stamp.ToString(9)
        << " <= " << last.stamp.ToString(9) << " (sample dropped)";
      return Status::Error(m.str());
    }
    const double dt = DurationSeconds(stamp, last.stamp);
    const Pose3 rel = Between(last.pose, odom_base);
    const double speed = TranslationNorm(rel) / dt;
    const double yaw_rate_dps = std::fabs(YawRad(rel)) * 180.0 / M_PI / dt;
    std::ostringstream m;
    if (speed > options_.max_speed_mps) {
      m << "wheel odometry jump: " << speed << " m/s > " << options_.max_speed_mps << " m/s";
    } else if (yaw_rate_dps > options_.max_yaw_rate_dps) {
      m << "wheel odometry jump: yaw rate " << yaw_rate_dps << " deg/s > "
        << options_.max_yaw_rate_dps << " deg/s";
    }
    if (!m.str().empty()) {
      s.jump_before = true;
      ++jumps_;
      status = Status::Error(m.str() + " at " + stamp.ToString());
    }
  }
  samples_.push_back(s);
  while (static_cast<int>(samples_.size()) > options_.max_samples) samples_.pop_front();
  return status;
}

long WheelOdometryBuffer::FloorIndex(Time t) const {
  auto it = std::upper_bound(samples_.begin(), samples_.end(), t,
                             [](Time a, const Sample& b) { return a < b.stamp; });
  return static_cast<long>(it - samples_.begin()) - 1;
}

Status WheelOdometryBuffer::PoseAt(Time t, Pose3* odom_base) const {
  if (samples_.empty()) return Status::Error("no wheel odometry received");
  const long i = FloorIndex(t);
  std::ostringstream m;
  if (i < 0) {
    m << "no wheel odometry at " << t.ToString() << ": before the first sample "
      << samples_.front().stamp.ToString();
    return Status::Error(m.str());
  }
  const Sample& a = samples_[i];
  if (a.stamp == t) {
    *odom_base = a.pose;
    return Status::Ok();
  }
  if (static_cast<size_t>(i) + 1 == samples_.size()) {
    const double ahead = DurationSeconds(t, a.stamp);
    if (ahead > options_.max_extrapolation_s || samples_.size() < 2 || a.jump_before) {
      m << "no wheel odometry at " << t.ToString() << ": " << ahead << " s after the newest sample";
      return Status::Error(m.str());
    }
    const Sample& p = samples_[i - 1];
    if (DurationSeconds(a.stamp, p.stamp) > options_.max_gap_s) {
      m << "no wheel odometry at " << t.ToString() << ": last samples too far apart";
      return Status::Error(m.str());
    }
    // Constant-velocity extrapolation of the last segment.
    const double s = 1.0 + ahead / DurationSeconds(a.stamp, p.stamp);
    Eigen::Matrix<double, 6, 1> twist = LogSE3(Between(p.pose, a.pose));
    *odom_base = p.pose * ExpSE3(twist * s);
    return Status::Ok();
  }
  const Sample& b = samples_[i + 1];
  const double span = DurationSeconds(b.stamp, a.stamp);
  if (span > options_.max_gap_s) {
    m << "wheel odometry gap: " << span << " s > " << options_.max_gap_s << " s around "
      << t.ToString();
    return Status::Error(m.str());
  }
  if (b.jump_before) {
    m << "wheel odometry jump between " << a.stamp.ToString() << " and " << b.stamp.ToString();
    return Status::Error(m.str());
  }
  *odom_base = Interpolate(a.pose, b.pose, DurationSeconds(t, a.stamp) / span);
  return Status::Ok();
}

Status WheelOdometryBuffer::RelativeMotion(Time from, Time to, Pose3* base_from_to) const {
  Pose3 a, b;
  Status sa = PoseAt(from, &a);
  if (!sa.ok()) return sa;
  Status sb = PoseAt(to, &b);
  if (!sb.ok()) return sb;
  // Every segment between the two stamps must be gap- and jump-free.
  const Time lo = std::min(from, to), hi = std::max(from, to);
  const long first = std::max(0L, FloorIndex(lo));
  for (long i = first + 1; i < static_cast<long>(samples_.size()) && samples_[i - 1].stamp < hi;
       ++i) {
    const double gap = DurationSeconds(samples_[i].stamp, samples_[i - 1].stamp);
    std::ostringstream m;
    if (samples_[i].jump_before) {
      m << "wheel odometry jump at " << samples_[i].stamp.ToString() << " between " << lo.ToString()
        << " and " << hi.ToString();
      return Status::Error(m.str());
    }
    if (gap > options_.max_gap_s) {
      m << "wheel odometry gap: " << gap << " s > " << options_.max_gap_s << " s between "
        << lo.ToString() << " and " << hi.ToString();
      return Status::Error(m.str());
    }
  }
  *base_from_to = Between(a, b);
  return Status::Ok();
}

void WheelOdometryBuffer::TrimBefore(Time t) {
  while (samples_.size() > 1 && samples_[1].stamp <= t) samples_.pop_front();
}

}  // namespace icgm
