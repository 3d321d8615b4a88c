#include "core/slam/wheel_feed.h"

#include <cmath>
#include <cstdint>

namespace icgm {

WheelFeed::WheelFeed(double lead_s, size_t max_pending)
    : lead_s_(lead_s), max_pending_(max_pending) {}

Time WheelFeed::Limit(Time frame_stamp) const {
  return Time::FromNanoseconds(frame_stamp.nanoseconds() +
                               static_cast<int64_t>(std::llround(lead_s_ * 1e9)));
}

bool WheelFeed::Add(Time stamp, const Pose3& odom_base) {
  if (received_any_ && stamp <= newest_) return false;
  received_any_ = true;
  newest_ = stamp;
  pending_.emplace_back(stamp, odom_base);
  if (pending_.size() > max_pending_) pending_.pop_front();
  return true;
}

bool WheelFeed::Covers(Time frame_stamp) const {
  return received_any_ && Limit(frame_stamp) <= newest_;
}

void WheelFeed::FeedUpTo(Time frame_stamp, const Sink& sink) {
  const Time limit = Limit(frame_stamp);
  while (!pending_.empty() && pending_.front().first <= limit) {
    sink(pending_.front().first, pending_.front().second);
    pending_.pop_front();
  }
}

}  // namespace icgm
