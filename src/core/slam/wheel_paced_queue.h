// Frames held until the wheel odometry they need has arrived, so a live front end is given the
// same wheel samples before each frame as icgm_slam_offline gives it (wheel_feed.h). A frame
// stamped t is ready once the feed covers t (the samples up to t + lead_s are in), or once newer
// data (frames or wheel samples) reaches t + max_wait_s, or once it has waited max_wait_s of wall
// time (e.g. at the end of a bag nothing newer comes). Without wheels every frame is ready at
// once. Frames leave in arrival order; beyond max_pending the oldest is dropped.
#pragma once

#include <chrono>
#include <cstddef>
#include <deque>
#include <utility>

#include "core/common/time.h"
#include "core/slam/wheel_feed.h"

namespace icgm {

struct WheelPacedQueueOptions {
  bool wheels = true;        // false: a camera without wheels, nothing to wait for
  double max_wait_s = 0.3;   // of message time and of wall time
  size_t max_pending = 100;  // frames held at most
};

template <typename Frame>
class WheelPacedQueue {
 public:
  using Clock = std::chrono::steady_clock;

  WheelPacedQueue(const WheelPacedQueueOptions& options, const WheelFeed* feed)
      : options_(options), feed_(feed) {}

  // Returns false when the oldest frame was dropped to make room.
  bool Push(Time stamp, Frame frame) {
    Note(stamp);
    held_.push_back({stamp, Clock::now(), std::move(frame)});
    if (held_.size() <= options_.max_pending) return true;
    held_.pop_front();
    return false;
  }
  // A wheel sample's (or any message's) stamp: newer data bounds the wait.
  void Note(Time stamp) {
    if (newest_ < stamp) newest_ = stamp;
  }
  // The oldest frame when it is ready, else nullptr.
  Frame* ReadyFront() {
    if (held_.empty()) return nullptr;
    Held& h = held_.front();
    const bool ready =
        !options_.wheels || feed_->Covers(h.stamp) ||
        DurationSeconds(newest_, h.stamp) >= options_.max_wait_s ||
        std::chrono::duration<double>(Clock::now() - h.received).count() >= options_.max_wait_s;
    return ready ? &h.frame : nullptr;
  }
  Time front_stamp() const { return held_.front().stamp; }
  void PopFront() { held_.pop_front(); }
  void Clear() { held_.clear(); }
  bool empty() const { return held_.empty(); }
  size_t size() const { return held_.size(); }

 private:
  struct Held {
    Time stamp;
    Clock::time_point received;
    Frame frame;
  };
  WheelPacedQueueOptions options_;
  const WheelFeed* feed_;
  std::deque<Held> held_;
  Time newest_;
};

}  // namespace icgm
