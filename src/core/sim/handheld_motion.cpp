#include "core/sim/handheld_motion.h"

#include <algorithm>
#include <cmath>
#include <string>

#include "core/common/status.h"

namespace icgm::sim {
namespace {

constexpr double kDeg = M_PI / 180.0;
// Hand shake: 1-5 Hz.
constexpr double kShakeMinPeriodS = 0.2;
constexpr double kShakeMaxPeriodS = 1.0;

Eigen::Matrix3d LevelFromOptical() {
  Eigen::Matrix3d level_from_optical;
  level_from_optical.col(0) = Eigen::Vector3d(0, -1, 0);  // optical x = right
  level_from_optical.col(1) = Eigen::Vector3d(0, 0, -1);  // optical y = down
  level_from_optical.col(2) = Eigen::Vector3d(1, 0, 0);   // optical z = forward
  return level_from_optical;
}

}  // namespace

std::vector<HandheldMotion::Wave> HandheldMotion::DrawWaves(Rng& rng, int count, double amplitude,
                                                            double min_period_s,
                                                            double max_period_s) {
  std::vector<Wave> waves(count);
  double total = 0.0;
  for (Wave& w : waves) {
    w.amplitude = Uniform(rng, 0.3, 1.0);
    w.omega_rad_per_s = 2.0 * M_PI / Uniform(rng, min_period_s, max_period_s);
    w.phase_rad = Uniform(rng, 0.0, 2.0 * M_PI);
    total += w.amplitude;
  }
  for (Wave& w : waves) w.amplitude *= amplitude / total;
  return waves;
}

double HandheldMotion::Sum(const std::vector<Wave>& waves, double t_s) {
  double sum = 0.0;
  for (const Wave& w : waves) sum += w.amplitude * std::sin(w.omega_rad_per_s * t_s + w.phase_rad);
  return sum;
}

HandheldMotion::HandheldMotion(const HandheldOptions& o, double duration_s, Rng& rng)
    : options_(o) {
  if (!o.recorded_trajectory.empty()) {
    recorded_ = ReadTumTrajectory(o.recorded_trajectory);
    SortByStamp(&recorded_);
    if (recorded_.size() < 2) {
      throw LoadError("recorded trajectory '" + o.recorded_trajectory + "' has fewer than 2 poses");
    }
    if (DurationSeconds(recorded_.back().stamp, recorded_.front().stamp) < o.recorded_start_s) {
      throw LoadError("recorded trajectory '" + o.recorded_trajectory + "' ends before " +
                      std::to_string(o.recorded_start_s) + " s");
    }
    recorded_start_inverse_ = Recorded(0.0).inverse();
    return;
  }
  const double period = o.drift_period_s;
  for (int axis = 0; axis < 3; ++axis) {
    // The hand moves up and down less than sideways.
    drift_[axis] = DrawWaves(rng, 3, axis == 2 ? 0.3 : 1.0, 0.6 * period, 1.6 * period);
  }
  pan_ = DrawWaves(rng, 2, o.pan_amplitude_deg * kDeg, 0.7 * o.pan_period_s, 1.4 * o.pan_period_s);
  tilt_ =
      DrawWaves(rng, 2, o.tilt_amplitude_deg * kDeg, 0.7 * o.pan_period_s, 1.4 * o.pan_period_s);
  roll_ =
      DrawWaves(rng, 2, o.roll_amplitude_deg * kDeg, 0.7 * o.pan_period_s, 1.4 * o.pan_period_s);
  for (int axis = 0; axis < 3; ++axis) {
    shake_[axis] = DrawWaves(rng, 3, o.jitter_m, kShakeMinPeriodS, kShakeMaxPeriodS);
    shake_angle_[axis] = DrawWaves(rng, 3, o.jitter_deg * kDeg, kShakeMinPeriodS, kShakeMaxPeriodS);
  }
  // Scale the drift to the requested mean speed over the sequence (finite differences at 100 Hz).
  const double step = 0.01;
  const int steps = std::max(1, static_cast<int>(std::ceil(duration_s / step)));
  double path = 0.0;
  for (int k = 0; k < steps; ++k) {
    double d2 = 0.0;
    for (int axis = 0; axis < 3; ++axis) {
      const double d = Sum(drift_[axis], (k + 1) * step) - Sum(drift_[axis], k * step);
      d2 += d * d;
    }
    path += std::sqrt(d2);
  }
  const double mean_speed = path / (steps * step);
  drift_scale_ = mean_speed > 1e-12 ? o.drift_speed_mps / mean_speed : 0.0;
}

Pose3 HandheldMotion::Recorded(double t_s) const {
  const double since_first =
      std::min(options_.recorded_start_s + std::max(t_s, 0.0),
               DurationSeconds(recorded_.back().stamp, recorded_.front().stamp));
  const Time t = Time::FromNanoseconds(recorded_.front().stamp.nanoseconds() +
                                       static_cast<int64_t>(std::llround(since_first * 1e9)));
  // Within [first, last] by construction; a hole longer than 1 s is bridged as well.
  return PoseAt(recorded_, t, 1.0).value_or(recorded_.back().pose);
}

Eigen::Vector3d HandheldMotion::Walk(double t) const {
  const double v = options_.walk_speed_mps;
  if (v <= 0.0) return Eigen::Vector3d::Zero();
  const double yaw = options_.yaw_deg * kDeg;
  const Eigen::Vector3d forward(std::cos(yaw), std::sin(yaw), 0.0);
  const Eigen::Vector3d left(-forward.y(), forward.x(), 0.0);
  const double step_rad = 2.0 * M_PI * options_.walk_step_hz * t;
  // The body rises in the middle of each step (twice per stride) and sways toward the foot
  // that stands (once per stride); both start at zero.
  return v * t * forward +
         options_.walk_bob_m * 0.5 * (1.0 - std::cos(step_rad)) * Eigen::Vector3d::UnitZ() +
         0.5 * options_.walk_bob_m * std::sin(0.5 * step_rad) * left;
}

Pose3 HandheldMotion::T_world_camera(double t) const {
  if (!recorded_.empty()) {
    Pose3 start = Pose3::Identity();
    start.linear() = (Eigen::AngleAxisd(options_.yaw_deg * kDeg, Eigen::Vector3d::UnitZ()) *
                      Eigen::AngleAxisd(options_.pitch_down_deg * kDeg, Eigen::Vector3d::UnitY()))
                         .toRotationMatrix() *
                     LevelFromOptical();
    start.translation() = Eigen::Vector3d(options_.x_m, options_.y_m, options_.height_m);
    return start * recorded_start_inverse_ * Recorded(t);
  }
  Eigen::Vector3d p(options_.x_m, options_.y_m, options_.height_m);
  p += Walk(t);
  for (int axis = 0; axis < 3; ++axis) {
    p[axis] += drift_scale_ * (Sum(drift_[axis], t) - Sum(drift_[axis], 0.0)) +
               Sum(shake_[axis], t);
  }
  const double yaw = options_.yaw_deg * kDeg + Sum(pan_, t) + Sum(shake_angle_[0], t);
  const double pitch_down =
      options_.pitch_down_deg * kDeg + Sum(tilt_, t) + Sum(shake_angle_[1], t);
  const double roll = Sum(roll_, t) + Sum(shake_angle_[2], t);
  const Eigen::Matrix3d level_from_optical = LevelFromOptical();
  Pose3 T = Pose3::Identity();
  T.linear() = (Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()) *
                Eigen::AngleAxisd(pitch_down, Eigen::Vector3d::UnitY()))
                   .toRotationMatrix() *
               level_from_optical * Eigen::AngleAxisd(roll, Eigen::Vector3d::UnitZ());
  T.translation() = p;
  return T;
}

PlanarPose HandheldMotion::ViewOnFloor(double t) const {
  const Pose3 T = T_world_camera(t);
  const Eigen::Vector3d forward = T.linear().col(2);
  PlanarPose p;
  p.x_m = T.translation().x();
  p.y_m = T.translation().y();
  p.yaw_rad = std::atan2(forward.y(), forward.x());
  return p;
}

}  // namespace icgm::sim
