#include "core/dataset/stamp_association.h"

#include <algorithm>
#include <cassert>
#include <cmath>
#include <cstdlib>

namespace icgm {

namespace {
struct Candidate {
  int64_t abs_dt_ns;
  size_t a;
  size_t b;
};
}  // namespace

std::vector<std::pair<size_t, size_t>> AssociateStamps(const std::vector<Time>& a,
                                                       const std::vector<Time>& b,
                                                       double max_dt_s) {
  assert(std::is_sorted(a.begin(), a.end()) && std::is_sorted(b.begin(), b.end()));
  // Clamped so the nanosecond conversion cannot overflow (1e6 s is wider than any sequence).
  const double window_s = std::isnan(max_dt_s) ? 0.0 : std::clamp(max_dt_s, 0.0, 1e6);
  const int64_t max_dt_ns = Time::FromSeconds(window_s).nanoseconds();
  // All pairs within the window: a sliding window over b, since both are sorted.
  std::vector<Candidate> candidates;
  size_t lo = 0;
  for (size_t i = 0; i < a.size(); ++i) {
    const int64_t t = a[i].nanoseconds();
    while (lo < b.size() && b[lo].nanoseconds() < t - max_dt_ns) ++lo;
    for (size_t j = lo; j < b.size() && b[j].nanoseconds() <= t + max_dt_ns; ++j) {
      candidates.push_back({std::llabs(b[j].nanoseconds() - t), i, j});
    }
  }
  std::sort(candidates.begin(), candidates.end(), [](const Candidate& x, const Candidate& y) {
    if (x.abs_dt_ns != y.abs_dt_ns) return x.abs_dt_ns < y.abs_dt_ns;
    return x.a != y.a ? x.a < y.a : x.b < y.b;
  });
  std::vector<bool> a_used(a.size(), false);
  std::vector<bool> b_used(b.size(), false);
  std::vector<std::pair<size_t, size_t>> pairs;
  for (const Candidate& c : candidates) {
    if (a_used[c.a] || b_used[c.b]) continue;
    a_used[c.a] = b_used[c.b] = true;
    pairs.emplace_back(c.a, c.b);
  }
  std::sort(pairs.begin(), pairs.end());
  return pairs;
}

}  // namespace icgm
