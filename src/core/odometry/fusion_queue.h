// Registration results on their way into the odometry fusion (thesis ch. 6.1.1.1), fused in
// stamp order. A failed registration waits for wheel data covering its stamp, so the wheel
// fallback has motion to interpolate, until the newest stamp seen (wheel sample or result) is
// `max_wait_for_wheel_s` past it, or more than `max_pending` results wait (then all are fused
// at once). A result not after the fusion's last stamp (time went backwards) is dropped.
// Not thread-safe.
#pragma once

#include <cstddef>
#include <deque>
#include <functional>

#include "core/common/pose.h"
#include "core/common/time.h"
#include "core/odometry/odometry_fusion.h"
#include "core/odometry/wheel_odometry_buffer.h"
#include "core/registration/rgbd_registration.h"

namespace icgm {

struct FusionQueueOptions {
  double max_wait_for_wheel_s = 0.3;  // of message time
  size_t max_pending = 5;             // results waiting before they are fused without waiting
};

// One fused result, as the fusion nodelet publishes it.
struct FusedResult {
  Time stamp;
  const RegistrationResult* registration = nullptr;  // valid during the callback
  Pose3 odom_camera_before;                          // the fused pose before this step
  double dt_s = 0.0;                                 // since the previous fused stamp
  FusionStep step;
};

class FusionQueue {
 public:
  explicit FusionQueue(const FusionQueueOptions& options = FusionQueueOptions())
      : options_(options) {}

  void Push(Time stamp, RegistrationResult result);
  // Fuses what can be fused now into `fusion` (initialized) with `wheel`: `fused` after each
  // step, `dropped` for each result whose time went backwards.
  void Drain(OdometryFusion* fusion, const WheelOdometryBuffer& wheel,
             const std::function<void(const FusedResult&)>& fused,
             const std::function<void(Time)>& dropped);
  void Clear() { queue_.clear(); }
  bool empty() const { return queue_.empty(); }
  size_t size() const { return queue_.size(); }

 private:
  struct Entry {
    Time stamp;
    RegistrationResult result;
  };
  void DrainOnce(bool force, OdometryFusion* fusion, const WheelOdometryBuffer& wheel,
                 const std::function<void(const FusedResult&)>& fused,
                 const std::function<void(Time)>& dropped);

  FusionQueueOptions options_;
  std::deque<Entry> queue_;
};

}  // namespace icgm
