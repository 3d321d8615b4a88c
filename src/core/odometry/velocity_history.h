// Constant-velocity prediction from the last few frame poses instead of the last step alone.
// A hand-held camera among walkers moves a few millimetres per frame while single registration
// steps err by one to three centimetres; the last step's velocity then predicts mostly that
// error. The velocity over several frames averages it out (the hand's inertia keeps the true
// velocity nearly constant over a fraction of a second).
#pragma once

#include <cstddef>
#include <deque>
#include <optional>
#include <utility>

#include "core/common/pose.h"
#include "core/common/status.h"
#include "core/common/time.h"

namespace icgm {

// How fast a hand can move a camera (0: no limit). A walker filling the view carries a
// registration at walking speed (1-2 m/s) where a hand moves the camera at 0.05-0.15 m/s.
struct MotionLimits {
  double max_speed_mps = 0.0;
  // Change of the velocity per second (translation).
  double max_accel_mps2 = 0.0;
  bool on() const { return max_speed_mps > 0.0 || max_accel_mps2 > 0.0; }
};

// Whether `step`, taken over dt_s, moves the camera no faster than max_speed_mps (true without a
// limit or without a positive dt_s).
bool WithinSpeed(const Pose3& step, double dt_s, double max_speed_mps);

// Whether a camera step `step` (T_prev_cur) over dt_s is one a hand can make: no faster than
// max_speed_mps and, with a `predicted` step (constant velocity), its velocity within
// max_accel_mps2 * dt_s of the predicted one. Ok, or the reason it is implausible.
Status CheckHandMotion(const Pose3& step, double dt_s, const Pose3* predicted,
                       const MotionLimits& limits);

class VelocityHistory {
 public:
  // `max_steps`: the velocity spans at most this many steps (>= 1); `max_gap_s`: a step longer
  // than this breaks the history (the velocity restarts after the gap).
  // `median`: the velocity is the per-component median of the single steps' twists instead of
  // the mean motion from the oldest to the newest pose (one jerk of the hand, or one step that
  // followed a walker, then does not set the velocity).
  // `from_rest`: while the history holds fewer than max_steps steps, the missing ones count as
  // standing still (the velocity is scaled by steps held / max_steps), so one early step does
  // not set the velocity alone.
  VelocityHistory(size_t max_steps, double max_gap_s, bool median = false, bool from_rest = false);

  // T_odom_camera of a frame, in stamp order (an older or equal stamp is ignored).
  void Add(Time stamp, const Pose3& odom_camera);
  void Clear() { poses_.clear(); }
  // Every kept pose re-expressed as `correction` * pose (a change of the frame the poses are
  // given in): the prediction is unchanged, later poses given in the new frame continue it
  // without a jump.
  void Rebase(const Pose3& correction);

  // T_prev_cur for a frame at `stamp` following the newest pose, moving with the body-frame twist
  // of the motion from the oldest to the newest kept pose (constant velocity over the span).
  // None with fewer than two poses or when `stamp` lies more than max_gap_s after the newest.
  std::optional<Pose3> PredictStep(Time stamp) const;
  // That velocity: the body-frame twist per second (pose.h order), none with fewer than two
  // poses.
  std::optional<Vec6> Twist() const;

  size_t size() const { return poses_.size(); }
  // Steps the prediction spans now (poses held - 1, at most max_steps), and at most.
  size_t steps() const { return poses_.empty() ? 0 : poses_.size() - 1; }
  size_t max_steps() const { return max_steps_; }

 private:
  size_t max_steps_;
  double max_gap_s_;
  bool median_;
  bool from_rest_;
  std::deque<std::pair<Time, Pose3>> poses_;
};

}  // namespace icgm
