#include "core/sim/frame_prefetcher.h"

#include <algorithm>
#include <utility>

namespace icgm::sim {

FramePrefetcher::FramePrefetcher(const Simulator& sim, size_t max_ahead, const RenderFlags& flags)
    : sim_(sim), max_ahead_(std::max<size_t>(1, max_ahead)), flags_(flags) {
  worker_ = std::thread([this] { Run(); });
}

FramePrefetcher::~FramePrefetcher() {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    stop_ = true;
  }
  changed_.notify_all();
  worker_.join();
}

void FramePrefetcher::Run() {
  for (size_t i = 0; i < sim_.size(); ++i) {
    {
      std::unique_lock<std::mutex> lock(mutex_);
      changed_.wait(lock, [this] { return stop_ || ready_.size() < max_ahead_; });
      if (stop_) return;
    }
    SimFrame frame = sim_.Render(i, flags_);  // outside the lock: the consumer keeps going
    {
      std::lock_guard<std::mutex> lock(mutex_);
      ready_.push_back(std::move(frame));
    }
    changed_.notify_all();
  }
}

bool FramePrefetcher::Next(SimFrame* frame) {
  std::unique_lock<std::mutex> lock(mutex_);
  if (taken_ >= sim_.size()) return false;
  changed_.wait(lock, [this] { return !ready_.empty(); });
  *frame = std::move(ready_.front());
  ready_.pop_front();
  ++taken_;
  lock.unlock();
  changed_.notify_all();
  return true;
}

}  // namespace icgm::sim
