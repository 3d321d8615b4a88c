// Reset of the motion prior when registration and prediction disagree for several frames.
// The constant-velocity prediction starts from the last fused pose; where the motion prior
// outweighs the registration, the fused pose follows the prediction, and a prediction that went
// wrong feeds on itself while the registrations, each to its keyframe, keep saying otherwise.
// The detector watches the registered pose's offset from the predicted one: when it exceeds
// disagreement_m in `frames` frames in a row, the offsets agree with each other within
// self_agreement_m (the registrations agree among themselves about where the camera is), and
// the registered poses move no faster than max_speed_mps (no walker carries them), the frame
// is to take its registered pose without the prior.
#pragma once

#include <deque>

#include "core/common/pose.h"
#include "core/common/time.h"

namespace icgm {

struct PriorResetOptions {
  double disagreement_m = 0.0;    // 0: off
  int frames = 3;                 // frames in a row
  double self_agreement_m = 0.0;  // offsets' spread about their mean (0: not checked)
  double max_speed_mps = 0.0;     // registered poses' speed over the streak (0: not checked)
  bool on() const { return disagreement_m > 0.0; }
};

class PriorResetDetector {
 public:
  explicit PriorResetDetector(const PriorResetOptions& options) : options_(options) {}

  // A frame registered at `registered` (T_odom_camera before the prior) where the prior
  // predicted `predicted`. True: the prior is to be reset at this frame (the streak restarts).
  bool Observe(Time stamp, const Pose3& registered, const Pose3& predicted);
  // A frame without a registration or a prediction breaks the streak.
  void Break() { streak_.clear(); }
  size_t streak() const { return streak_.size(); }

 private:
  struct Entry {
    Time stamp;
    Vec3 position;  // registered
    Vec3 offset;    // registered - predicted, odom frame
  };
  PriorResetOptions options_;
  std::deque<Entry> streak_;
};

}  // namespace icgm
