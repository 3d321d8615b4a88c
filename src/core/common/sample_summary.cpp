#include "core/common/sample_summary.h"

#include <algorithm>
#include <numeric>

namespace icgm {

namespace {
double SortedPercentile(const std::vector<double>& sorted, double q) {
  q = std::clamp(q, 0.0, 1.0);
  return sorted[std::min(sorted.size() - 1, static_cast<size_t>(q * (sorted.size() - 1) + 0.5))];
}
}  // namespace

SampleSummary Summarize(std::vector<double> v) {
  SampleSummary s;
  if (v.empty()) return s;
  std::sort(v.begin(), v.end());
  const size_t n = v.size();
  s.count = n;
  s.mean = std::accumulate(v.begin(), v.end(), 0.0) / n;
  s.median = n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
  s.p95 = SortedPercentile(v, 0.95);
  s.max = v.back();
  return s;
}

double Percentile(std::vector<double> v, double q) {
  if (v.empty()) return 0.0;
  std::sort(v.begin(), v.end());
  return SortedPercentile(v, q);
}

}  // namespace icgm
