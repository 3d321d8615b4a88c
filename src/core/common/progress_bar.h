// Terminal progress bar for offline tools: "[=====>    ] 412/798  52%  38.1 fps  ETA 10s".
// Redraws in place on a TTY, prints sparse lines otherwise (CI logs stay short).
#pragma once

#include <chrono>
#include <cstddef>
#include <cstdio>
#include <string>

namespace icgm {

class ProgressBar {
 public:
  ProgressBar(size_t total, std::string label, std::FILE* out = stderr);
  // Marks `done` items complete; cheap to call every item (redraws at most ~10 times/s).
  void Update(size_t done);
  // Draws the final state and a newline.
  void Finish();
  // The same with `done` of the total complete: a run that stopped early shows where.
  void Finish(size_t done);

 private:
  void Draw(size_t done, bool final_draw);
  size_t total_;
  std::string label_;
  std::FILE* out_;
  bool tty_;
  std::chrono::steady_clock::time_point start_;
  std::chrono::steady_clock::time_point last_draw_;
  int last_decile_ = -1;
  bool finished_ = false;
};

}  // namespace icgm
