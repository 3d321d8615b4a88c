#include "core/eval/error_stats.h"

#include <algorithm>
#include <cmath>

namespace icgm {

ErrorStats ComputeErrorStats(const std::vector<double>& errors) {
  ErrorStats s;
  if (errors.empty()) return s;
  s.count = errors.size();
  double sum = 0.0;
  double sum_sq = 0.0;
  for (double e : errors) {
    sum += e;
    sum_sq += e * e;
  }
  const double n = static_cast<double>(s.count);
  s.mean = sum / n;
  s.rmse = std::sqrt(sum_sq / n);
  s.std_dev = std::sqrt(std::max(0.0, sum_sq / n - s.mean * s.mean));
  std::vector<double> sorted = errors;
  std::sort(sorted.begin(), sorted.end());
  const size_t mid = s.count / 2;
  s.median = s.count % 2 ? sorted[mid] : 0.5 * (sorted[mid - 1] + sorted[mid]);
  s.min = sorted.front();
  s.max = sorted.back();
  return s;
}

}  // namespace icgm
