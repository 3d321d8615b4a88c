// CPU time of the calling thread (ms): per-frame costs that other processes sharing the cores do
// not inflate, for benchmarks and per-frame timing reports.
#pragma once

#include <ctime>

namespace icgm {

inline double ThreadCpuMs() {
  timespec ts{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
  return 1e3 * static_cast<double>(ts.tv_sec) + 1e-6 * static_cast<double>(ts.tv_nsec);
}

}  // namespace icgm
