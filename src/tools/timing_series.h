// Per-call timings of a benchmark (ms) and their summary line for a range of the calls (e.g.
// the last 10%, once a map or dictionary has grown).
#pragma once

#include <cstdio>
#include <utility>
#include <vector>

#include "core/common/sample_summary.h"

namespace icgm::tools {

struct TimingSeries {
  std::vector<double> ms;
  void Add(double v) { ms.push_back(v); }
  // "  label    mean 1.234 ms  p95 2.345 ms  max 3.456 ms" over entries [from, end); nothing
  // when that range is empty.
  void Print(const char* label, size_t from) const {
    if (from >= ms.size()) return;
    const SampleSummary s = Summarize(std::vector<double>(ms.begin() + static_cast<long>(from),
                                                          ms.end()));
    std::printf("  %-40s mean %7.3f ms  p95 %7.3f ms  max %7.3f ms\n", label, s.mean, s.p95,
                s.max);
  }
};

}  // namespace icgm::tools
