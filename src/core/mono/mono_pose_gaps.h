// Frames of a monocular run that end without a pose, by cause: before the first map, tracking
// lost while the map is kept (found again or still lost at the end), tracking lost until the map
// was dropped (the reset), and the re-initialization after a reset. A re-initialization's
// reference frame gets its pose on the frame that initializes; it is then no longer counted.
#pragma once

#include <cstddef>
#include <utility>
#include <vector>

#include "core/common/time.h"
#include "core/mono/mono_odometry.h"

namespace icgm {

enum class MonoPoseGapCause { kNotInitialized, kLost, kLostThenReset, kReinitializing };

struct MonoFramesWithoutPose {
  size_t not_initialized = 0;
  size_t lost = 0;  // tracking lost, the map kept (tracked again later, or the run ended)
  size_t lost_then_reset = 0;  // tracking lost, then the map dropped (the reset frame counted)
  size_t reinitializing = 0;
  size_t total() const { return not_initialized + lost + lost_then_reset + reinitializing; }
};

class MonoPoseGapCounter {
 public:
  // The results of a run's frames, in order.
  void Add(const MonoFrameResult& result);
  // All frames without a pose so far, and those with from < stamp < to.
  MonoFramesWithoutPose Counts() const;
  MonoFramesWithoutPose CountsBetween(Time from, Time to) const;

 private:
  std::vector<std::pair<Time, MonoPoseGapCause>> frames_;  // without a pose, in order
  size_t lost_run_begin_ = 0;  // index in frames_ of the current run of lost frames
  bool in_lost_run_ = false;
  bool had_map_ = false;
};

}  // namespace icgm
