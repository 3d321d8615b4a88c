#include "core/odometry/prior_reset.h"

#include <algorithm>

namespace icgm {

bool PriorResetDetector::Observe(Time stamp, const Pose3& registered, const Pose3& predicted) {
  if (!options_.on()) return false;
  const Vec3 offset = registered.translation() - predicted.translation();
  if (offset.norm() <= options_.disagreement_m) {
    streak_.clear();
    return false;
  }
  streak_.push_back({stamp, registered.translation(), offset});
  const size_t frames = static_cast<size_t>(std::max(1, options_.frames));
  while (streak_.size() > frames) streak_.pop_front();
  if (streak_.size() < frames) return false;
  if (options_.self_agreement_m > 0.0) {
    Vec3 mean = Vec3::Zero();
    for (const Entry& e : streak_) mean += e.offset / static_cast<double>(streak_.size());
    for (const Entry& e : streak_) {
      if ((e.offset - mean).norm() > options_.self_agreement_m) return false;
    }
  }
  if (options_.max_speed_mps > 0.0) {
    for (size_t i = 1; i < streak_.size(); ++i) {
      const double dt_s = DurationSeconds(streak_[i].stamp, streak_[i - 1].stamp);
      if (dt_s > 0.0 &&
          (streak_[i].position - streak_[i - 1].position).norm() > options_.max_speed_mps * dt_s) {
        return false;
      }
    }
  }
  streak_.clear();
  return true;
}

}  // namespace icgm
