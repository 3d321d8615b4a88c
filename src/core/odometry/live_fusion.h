// The odometry fusion of a running robot (thesis ch. 6.1.1.1), fed message by message: wheel
// samples and registration results (the front end's vision steps, VisionStepChain) in any
// interleaving. Results wait until Start (the base -> camera extrinsic known), which places the
// fusion at the oldest waiting result's reference frame; then they are fused in stamp order by
// the FusionQueue (a failed registration waits, bounded, for wheel data covering its stamp).
// Not thread-safe: one caller at a time.
#pragma once

#include <functional>
#include <memory>
#include <optional>

#include "core/common/pose.h"
#include "core/common/status.h"
#include "core/common/time.h"
#include "core/odometry/fusion_queue.h"
#include "core/odometry/odometry_fusion.h"
#include "core/odometry/wheel_odometry_buffer.h"

namespace icgm {

class LiveFusion {
 public:
  using FusedFn = std::function<void(const FusedResult&)>;
  using DroppedFn = std::function<void(Time stamp)>;  // a result whose time went backwards

  LiveFusion(const FusionOptions& fusion, const WheelOdometryOptions& wheel,
             const FusionQueueOptions& queue);

  // A T_odom_base sample; see WheelOdometryBuffer::Add.
  Status AddWheelOdometry(Time stamp, const Pose3& odom_base);
  // The registration of the frame at `stamp` relative to the one at `reference_stamp`.
  void Push(Time stamp, Time reference_stamp, RegistrationResult result);

  // The fusion (fusion.base_to_camera replaced by `base_to_camera`) starts at the oldest waiting
  // result's reference stamp, returned (nullopt: no result waits, nothing started).
  std::optional<Time> Start(const Pose3& base_to_camera);
  bool started() const { return fusion_ != nullptr; }
  void Clear();  // drops the waiting results

  // After Start: fuses what can be fused now, in order.
  void Drain(const FusedFn& fused, const DroppedFn& dropped);

  const OdometryFusion* fusion() const { return fusion_.get(); }
  size_t waiting() const { return queue_.size(); }

 private:
  FusionOptions options_;
  WheelOdometryBuffer wheel_;
  FusionQueue queue_;
  std::optional<Time> first_reference_;  // of the oldest waiting result
  std::unique_ptr<OdometryFusion> fusion_;
};

}  // namespace icgm
