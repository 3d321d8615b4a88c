// Backpressure between a frame producer and a slower consumer that answers each frame it takes
// from its input queue (the feature extraction and the registration of a live pipeline): a new
// frame is admitted only while fewer than max_frames admitted frames are still unanswered, so no
// CPU is spent on a frame the consumer's queues would drop; the frames not admitted are counted
// as skipped. The consumer takes frames in stamp order, so an answer for the frame stamped t
// answers every admitted frame stamped up to t (frames the consumer dropped, could not pair or
// takes as its first reference never get an answer of their own).
// The limit holds only once the consumer has answered a frame: before that (a consumer still
// starting, waiting for its extrinsic, or none at all) every frame is admitted. When nothing has
// been answered for stall_s of wall time while a frame has been in flight that long (a stalled
// or vanished consumer), or a frame is stamped before the newest admitted one (a replay starting
// again), the frames in flight are forgotten and counted.
#pragma once

#include <chrono>
#include <cstddef>
#include <deque>

#include "core/common/status.h"
#include "core/common/time.h"

namespace icgm {

struct InFlightLimitOptions {
  int max_frames = 5;    // admitted frames at most without an answer; 0: no limit
  double stall_s = 1.0;  // wall time without an answer after which frames in flight are forgotten
};

// Ok, or the option at fault: max_frames >= 0, stall_s > 0.
Status Validate(const InFlightLimitOptions& options);

class InFlightLimit {
 public:
  using Clock = std::chrono::steady_clock;

  explicit InFlightLimit(const InFlightLimitOptions& options) : options_(options) {}

  // true: the frame stamped `stamp` is processed (it is now in flight); false: skip it.
  bool Admit(Time stamp, Clock::time_point now = Clock::now());
  // The consumer's answer for the frame stamped `stamp`.
  void Answered(Time stamp, Clock::time_point now = Clock::now());

  bool active() const { return active_; }
  size_t in_flight() const { return in_flight_.size(); }
  size_t admitted() const { return admitted_; }
  size_t skipped() const { return skipped_; }
  size_t forgotten() const { return forgotten_; }  // in flight when a stall or restart came

 private:
  void Forget();

  InFlightLimitOptions options_;
  struct Admitted {
    Time stamp;
    Clock::time_point at;
  };
  std::deque<Admitted> in_flight_;  // admitted, unanswered, in stamp order
  bool active_ = false;             // an answer came
  Clock::time_point last_answer_;
  size_t admitted_ = 0;
  size_t skipped_ = 0;
  size_t forgotten_ = 0;
};

}  // namespace icgm
