#include "core/place/temporal_consistency.h"

#include <cstdlib>
#include <utility>

namespace icgm {

bool TemporalConsistency::Consistent(int query, int candidate) const {
  const int k = options_.consistent_queries;
  if (k <= 0) return true;
  for (int back = 1; back <= k; ++back) {
    const int previous = query - back;
    bool agrees = false;
    for (const Entry& e : history_) {
      if (e.query != previous) continue;
      for (int c : e.candidates) {
        if (std::abs(c - candidate) <= options_.window_images) agrees = true;
      }
    }
    if (!agrees) return false;
  }
  return true;
}

void TemporalConsistency::Record(int query, std::vector<int> candidates) {
  if (options_.consistent_queries <= 0) return;
  history_.push_back({query, std::move(candidates)});
  while (static_cast<int>(history_.size()) > options_.consistent_queries) history_.pop_front();
}

}  // namespace icgm
