// CPU time a nodelet's callback spends per frame (the calling thread's CPU clock, so other
// load on the machine does not count), reported every `every` frames.
#pragma once

#include <time.h>

#include <cstddef>

namespace icgm::nodelets {

class CpuMeter {
 public:
  explicit CpuMeter(size_t every = 100) : every_(every) {}
  void Start() { start_ms_ = NowMs(); }
  // Ends one frame; true (with the mean over the last `every` frames) when a report is due.
  bool Stop(double* mean_ms) { return Add(NowMs() - start_ms_, mean_ms); }
  // One frame measured elsewhere (`ms` of CPU); as Stop.
  bool Add(double ms, double* mean_ms) {
    sum_ms_ += ms;
    if (++count_ < every_) return false;
    *mean_ms = sum_ms_ / count_;
    sum_ms_ = 0;
    count_ = 0;
    return true;
  }

 private:
  static double NowMs() {
    timespec ts{};
    clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
    return ts.tv_sec * 1e3 + ts.tv_nsec * 1e-6;
  }
  size_t every_;
  size_t count_ = 0;
  double start_ms_ = 0;
  double sum_ms_ = 0;
};

}  // namespace icgm::nodelets
