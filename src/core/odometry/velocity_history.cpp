#include "core/odometry/velocity_history.h"

#include <algorithm>
#include <string>
#include <vector>

namespace icgm {

bool WithinSpeed(const Pose3& step, double dt_s, double max_speed_mps) {
  return max_speed_mps <= 0.0 || !(dt_s > 0.0) || TranslationNorm(step) <= max_speed_mps * dt_s;
}

Status CheckHandMotion(const Pose3& step, double dt_s, const Pose3* predicted,
                       const MotionLimits& limits) {
  if (!(dt_s > 0.0)) return Status::Ok();
  if (!WithinSpeed(step, dt_s, limits.max_speed_mps)) {
    return Status::Error("step of " + std::to_string(TranslationNorm(step) / dt_s) +
                         " m/s exceeds " + std::to_string(limits.max_speed_mps) + " m/s");
  }
  if (predicted && limits.max_accel_mps2 > 0.0) {
    const double change_mps = (step.translation() - predicted->translation()).norm() / dt_s;
    if (change_mps > limits.max_accel_mps2 * dt_s) {
      return Status::Error("velocity change of " + std::to_string(change_mps / dt_s) +
                           " m/s^2 exceeds " + std::to_string(limits.max_accel_mps2) + " m/s^2");
    }
  }
  return Status::Ok();
}

VelocityHistory::VelocityHistory(size_t max_steps, double max_gap_s, bool median, bool from_rest)
    : max_steps_(std::max<size_t>(1, max_steps)),
      max_gap_s_(max_gap_s),
      median_(median),
      from_rest_(from_rest) {}

void VelocityHistory::Add(Time stamp, const Pose3& odom_camera) {
  if (!poses_.empty()) {
    if (stamp <= poses_.back().first) return;
    if (DurationSeconds(stamp, poses_.back().first) > max_gap_s_) poses_.clear();
  }
  poses_.emplace_back(stamp, odom_camera);
  while (poses_.size() > max_steps_ + 1) poses_.pop_front();
}

void VelocityHistory::Rebase(const Pose3& correction) {
  for (auto& entry : poses_) entry.second = Orthonormalized(correction * entry.second);
}

std::optional<Pose3> VelocityHistory::PredictStep(Time stamp) const {
  if (poses_.empty()) return std::nullopt;
  const double dt_s = DurationSeconds(stamp, poses_.back().first);
  if (!(dt_s > 0.0) || dt_s > max_gap_s_) return std::nullopt;
  const std::optional<Vec6> twist = Twist();
  if (!twist) return std::nullopt;
  return Orthonormalized(ExpSE3(*twist * dt_s));
}

std::optional<Vec6> VelocityHistory::Twist() const {
  if (poses_.size() < 2) return std::nullopt;
  const auto& [t0, oldest] = poses_.front();
  const auto& [t1, newest] = poses_.back();
  const double span_s = DurationSeconds(t1, t0);
  if (!(span_s > 0.0)) return std::nullopt;
  Vec6 twist = LogSE3(Between(oldest, newest)) / span_s;
  if (median_ && poses_.size() > 2) {
    std::vector<Eigen::Matrix<double, 6, 1>> steps;
    for (size_t i = 1; i < poses_.size(); ++i) {
      const double dt = DurationSeconds(poses_[i].first, poses_[i - 1].first);
      if (dt > 0.0) steps.push_back(LogSE3(Between(poses_[i - 1].second, poses_[i].second)) / dt);
    }
    std::vector<double> component(steps.size());
    for (int c = 0; c < 6; ++c) {
      for (size_t i = 0; i < steps.size(); ++i) component[i] = steps[i][c];
      const size_t mid = component.size() / 2;
      std::nth_element(component.begin(), component.begin() + mid, component.end());
      double value = component[mid];
      if (component.size() % 2 == 0) {
        value = 0.5 * (value + *std::max_element(component.begin(), component.begin() + mid));
      }
      twist[c] = value;
    }
  }
  if (from_rest_ && poses_.size() - 1 < max_steps_) {
    twist *= static_cast<double>(poses_.size() - 1) / static_cast<double>(max_steps_);
  }
  if (!twist.allFinite()) return std::nullopt;
  return twist;
}

}  // namespace icgm
