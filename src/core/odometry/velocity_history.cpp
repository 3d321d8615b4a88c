#include "core/odometry/velocity_history.h"

#include <algorithm>

namespace icgm {

VelocityHistory::VelocityHistory(size_t max_steps, double max_gap_s)
    : max_steps_(std::max<size_t>(1, max_steps)), max_gap_s_(max_gap_s) {}

void VelocityHistory::Add(Time stamp, const Pose3& odom_camera) {
  if (!poses_.empty()) {
    if (stamp <= poses_.back().first) return;
    if (DurationSeconds(stamp, poses_.back().first) > max_gap_s_) poses_.clear();
  }
  poses_.emplace_back(stamp, odom_camera);
  while (poses_.size() > max_steps_ + 1) poses_.pop_front();
}

std::optional<Pose3> VelocityHistory::PredictStep(Time stamp) const {
  if (poses_.size() < 2) return std::nullopt;
  const auto& [t0, oldest] = poses_.front();
  const auto& [t1, newest] = poses_.back();
  const double span_s = DurationSeconds(t1, t0);
  const double dt_s = DurationSeconds(stamp, t1);
  if (!(span_s > 0.0) || !(dt_s > 0.0) || dt_s > max_gap_s_) return std::nullopt;
  const Eigen::Matrix<double, 6, 1> twist = LogSE3(Between(oldest, newest)) / span_s;
  if (!twist.allFinite()) return std::nullopt;
  return Orthonormalized(ExpSE3(twist * dt_s));
}

}  // namespace icgm
