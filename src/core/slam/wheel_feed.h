// Wheel odometry handed to the front end the same way offline and live: before a frame stamped
// t is processed, every sample up to t + lead_s is given to it, in time order (a live system
// has received those by then; later ones are not yet known). icgm_slam_offline, RunSlam and the
// registration nodelet feed RgbdFrontend / SlamSystem through it, so the front end sees the
// same wheel data whichever way the frames come.
#pragma once

#include <cstddef>
#include <deque>
#include <functional>
#include <utility>

#include "core/common/pose.h"
#include "core/common/time.h"

namespace icgm {

class WheelFeed {
 public:
  using Sink = std::function<void(Time stamp, const Pose3& odom_base)>;

  // `max_pending`: older samples are dropped beyond this many not yet fed.
  explicit WheelFeed(double lead_s = 0.05, size_t max_pending = 20000);

  // A received T_odom_base sample; false (dropped) when it is not newer than the last one.
  bool Add(Time stamp, const Pose3& odom_base);
  // The samples up to frame_stamp + lead_s are all in: one at or after that instant arrived.
  bool Covers(Time frame_stamp) const;
  // Gives `sink` every pending sample up to frame_stamp + lead_s, oldest first.
  void FeedUpTo(Time frame_stamp, const Sink& sink);

  bool received_any() const { return received_any_; }
  double lead_s() const { return lead_s_; }

 private:
  Time Limit(Time frame_stamp) const;

  double lead_s_;
  size_t max_pending_;
  std::deque<std::pair<Time, Pose3>> pending_;
  bool received_any_ = false;
  Time newest_;
};

}  // namespace icgm
