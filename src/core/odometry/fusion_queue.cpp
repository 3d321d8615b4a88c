#include "core/odometry/fusion_queue.h"

#include <utility>

namespace icgm {

void FusionQueue::Push(Time stamp, RegistrationResult result) {
  queue_.push_back({stamp, std::move(result)});
}

void FusionQueue::Drain(OdometryFusion* fusion, const WheelOdometryBuffer& wheel,
                        const std::function<void(const FusedResult&)>& fused,
                        const std::function<void(Time)>& dropped) {
  DrainOnce(false, fusion, wheel, fused, dropped);
  if (queue_.size() > options_.max_pending) DrainOnce(true, fusion, wheel, fused, dropped);
}

void FusionQueue::DrainOnce(bool force, OdometryFusion* fusion, const WheelOdometryBuffer& wheel,
                            const std::function<void(const FusedResult&)>& fused,
                            const std::function<void(Time)>& dropped) {
  while (!queue_.empty()) {
    const Entry& entry = queue_.front();
    Time newest = wheel.newest();
    if (newest < queue_.back().stamp) newest = queue_.back().stamp;
    if (!entry.result.status.ok() && !force && (wheel.empty() || wheel.newest() < entry.stamp) &&
        DurationSeconds(newest, entry.stamp) < options_.max_wait_for_wheel_s) {
      return;
    }
    if (entry.stamp <= fusion->stamp()) {
      if (dropped) dropped(entry.stamp);
      queue_.pop_front();
      continue;
    }
    FusedResult out;
    out.stamp = entry.stamp;
    out.registration = &entry.result;
    out.odom_camera_before = fusion->odom_camera();
    out.dt_s = DurationSeconds(entry.stamp, fusion->stamp());
    out.step = fusion->Update(
        entry.stamp, entry.result.status.ok() ? &entry.result.relative_pose : nullptr, &wheel);
    if (fused) fused(out);
    queue_.pop_front();
  }
}

}  // namespace icgm
