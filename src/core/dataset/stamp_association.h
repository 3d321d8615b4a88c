// One-to-one association of two timestamp sequences, as the TUM RGB-D benchmark's
// associate.py does: all pairs within max_dt_s are candidates, accepted greedily in order of
// increasing |dt| while neither element is taken yet.
#pragma once

#include <utility>
#include <vector>

#include "core/common/time.h"

namespace icgm {

// Returns (index into a, index into b) pairs, sorted by index into a. Both inputs must be
// sorted ascending (asserted in debug builds). Ties in |dt| resolve to the lower indices, so
// the result is deterministic. max_dt_s is clamped to [0, 1e6] s (NaN counts as 0).
std::vector<std::pair<size_t, size_t>> AssociateStamps(const std::vector<Time>& a,
                                                       const std::vector<Time>& b, double max_dt_s);

}  // namespace icgm
