// Temporal consistency of loop hypotheses (PIRF-nav 2.0, Kawewong et al. 2011; iBoW-LCD,
// Garcia-Fidalgo & Ortiz 2018): a revisit is seen by several consecutive queries, each matching
// a neighbouring earlier place, while a look-alike usually fools one query alone. A hypothesis
// q -> c is accepted when each of the `consistent_queries` queries q-1, ..., q-k had some
// hypothesis within `window_images` of c. The first k queries of a revisit are therefore never
// accepted: the check trades recall for precision.
#pragma once

#include <deque>
#include <vector>

#include "core/place/place_options.h"

namespace icgm {

class TemporalConsistency {
 public:
  explicit TemporalConsistency(const TemporalConsistencyOptions& options) : options_(options) {}

  // True when `candidate` is consistent with the hypotheses recorded for the queries before
  // `query` (always true when the check is off).
  bool Consistent(int query, int candidate) const;
  // Records the hypotheses (earlier images) of `query`; queries must increase. An empty list
  // (no hypothesis, or a frame that claimed nothing) breaks every chain through it.
  void Record(int query, std::vector<int> candidates);

 private:
  struct Entry {
    int query;
    std::vector<int> candidates;
  };
  TemporalConsistencyOptions options_;
  std::deque<Entry> history_;  // the last consistent_queries queries, oldest first
};

}  // namespace icgm
