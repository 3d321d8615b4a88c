// Summary statistics of a list of non-negative error magnitudes (RMSE, mean, median, ...),
// the figures the TUM RGB-D benchmark scripts report.
#pragma once

#include <cstddef>
#include <vector>

namespace icgm {

struct ErrorStats {
  size_t count = 0;
  double rmse = 0.0;
  double mean = 0.0;
  double median = 0.0;   // mean of the two middle values for an even count
  double std_dev = 0.0;  // population standard deviation
  double min = 0.0;
  double max = 0.0;
};

// All fields 0 for an empty input.
ErrorStats ComputeErrorStats(const std::vector<double>& errors);

}  // namespace icgm
