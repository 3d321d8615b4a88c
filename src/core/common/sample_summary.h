// Summary statistics of a sample of measurements (timings, errors) for benchmark reports.
#pragma once

#include <cstddef>
#include <vector>

namespace icgm {

struct SampleSummary {
  size_t count = 0;
  double mean = 0.0;
  double median = 0.0;  // mean of the two middle values for an even count
  double p95 = 0.0;     // nearest-rank 95th percentile
  double max = 0.0;
};

// All fields 0 for an empty sample.
SampleSummary Summarize(std::vector<double> samples);

// Nearest-rank percentile, q in [0, 1] (0: min, 1: max); 0 for an empty sample.
double Percentile(std::vector<double> samples, double q);

}  // namespace icgm
