#include "core/odometry/live_fusion.h"

#include <utility>

namespace icgm {

LiveFusion::LiveFusion(const FusionOptions& fusion, const WheelOdometryOptions& wheel,
                       const FusionQueueOptions& queue)
    : options_(fusion), wheel_(wheel), queue_(queue) {}

Status LiveFusion::AddWheelOdometry(Time stamp, const Pose3& odom_base) {
  return wheel_.Add(stamp, odom_base);
}

void LiveFusion::Push(Time stamp, Time reference_stamp, RegistrationResult result) {
  if (queue_.empty()) first_reference_ = reference_stamp;
  queue_.Push(stamp, std::move(result));
}

std::optional<Time> LiveFusion::Start(const Pose3& base_to_camera) {
  if (queue_.empty() || !first_reference_) return std::nullopt;
  FusionOptions options = options_;
  options.base_to_camera = base_to_camera;
  fusion_ = std::make_unique<OdometryFusion>(options);
  fusion_->Initialize(*first_reference_, &wheel_);
  return first_reference_;
}

void LiveFusion::Clear() {
  queue_.Clear();
  first_reference_.reset();
}

void LiveFusion::Drain(const FusedFn& fused, const DroppedFn& dropped) {
  if (fusion_) queue_.Drain(fusion_.get(), wheel_, fused, dropped);
}

}  // namespace icgm
