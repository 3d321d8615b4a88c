#include "core/mono/mono_pose_gaps.h"

#include <algorithm>

namespace icgm {

void MonoPoseGapCounter::Add(const MonoFrameResult& r) {
  if (r.initialized) {
    // The reference frame got its pose now.
    const auto it = std::find_if(frames_.rbegin(), frames_.rend(),
                                 [&](const auto& f) { return f.first == r.reference_stamp; });
    if (it != frames_.rend()) frames_.erase(std::next(it).base());
    in_lost_run_ = false;
  }
  if (r.has_pose) {
    had_map_ = true;
    in_lost_run_ = false;
    return;
  }
  if (r.reset) {
    frames_.emplace_back(r.stamp, MonoPoseGapCause::kLostThenReset);
    if (in_lost_run_) {
      for (size_t i = lost_run_begin_; i < frames_.size(); ++i) {
        frames_[i].second = MonoPoseGapCause::kLostThenReset;
      }
    }
    in_lost_run_ = false;
    return;
  }
  if (r.state == MonoState::kInitializing) {
    frames_.emplace_back(
        r.stamp, had_map_ ? MonoPoseGapCause::kReinitializing : MonoPoseGapCause::kNotInitialized);
    return;
  }
  if (!in_lost_run_) {
    in_lost_run_ = true;
    lost_run_begin_ = frames_.size();
  }
  frames_.emplace_back(r.stamp, MonoPoseGapCause::kLost);
}

MonoFramesWithoutPose MonoPoseGapCounter::Counts() const {
  MonoFramesWithoutPose c;
  for (const auto& [stamp, cause] : frames_) {
    switch (cause) {
      case MonoPoseGapCause::kNotInitialized:
        ++c.not_initialized;
        break;
      case MonoPoseGapCause::kLost:
        ++c.lost;
        break;
      case MonoPoseGapCause::kLostThenReset:
        ++c.lost_then_reset;
        break;
      case MonoPoseGapCause::kReinitializing:
        ++c.reinitializing;
        break;
    }
  }
  return c;
}

MonoFramesWithoutPose MonoPoseGapCounter::CountsBetween(Time from, Time to) const {
  MonoPoseGapCounter part;
  for (const auto& f : frames_) {
    if (from < f.first && f.first < to) part.frames_.push_back(f);
  }
  return part.Counts();
}

}  // namespace icgm
