#include "core/slam/in_flight_limit.h"

#include <algorithm>

namespace icgm {

Status Validate(const InFlightLimitOptions& options) {
  if (options.max_frames < 0) return Status::Error("max_frames must be >= 0 (0: no limit)");
  if (!(options.stall_s > 0.0)) return Status::Error("stall_s must be > 0");
  return Status::Ok();
}

bool InFlightLimit::Admit(Time stamp, Clock::time_point now) {
  if (!in_flight_.empty()) {
    const Clock::time_point since = std::max(last_answer_, in_flight_.front().at);
    const bool stalled = std::chrono::duration<double>(now - since).count() >= options_.stall_s;
    if (stalled || stamp <= in_flight_.back().stamp) Forget();
  }
  if (active_ && options_.max_frames > 0 &&
      in_flight_.size() >= static_cast<size_t>(options_.max_frames)) {
    ++skipped_;
    return false;
  }
  in_flight_.push_back({stamp, now});
  ++admitted_;
  return true;
}

void InFlightLimit::Answered(Time stamp, Clock::time_point now) {
  active_ = true;
  last_answer_ = now;
  while (!in_flight_.empty() && in_flight_.front().stamp <= stamp) in_flight_.pop_front();
}

void InFlightLimit::Forget() {
  forgotten_ += in_flight_.size();
  in_flight_.clear();
}

}  // namespace icgm
