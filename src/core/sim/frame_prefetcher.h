// Renders simulator frames on a worker thread ahead of a consumer (e.g. a bag writer), so
// rendering and writing overlap. Frames come out in index order and are identical to
// Simulator::Render(i).
#pragma once

#include <condition_variable>
#include <deque>
#include <mutex>
#include <thread>

#include "core/sim/simulator.h"

namespace icgm::sim {

class FramePrefetcher {
 public:
  // Starts rendering frames [0, sim.size()) with at most `max_ahead` (>= 1) frames buffered.
  // `sim` must outlive the prefetcher.
  FramePrefetcher(const Simulator& sim, size_t max_ahead = 4,
                  const RenderFlags& flags = RenderFlags());
  // Stops the worker (frames not taken are discarded).
  ~FramePrefetcher();
  FramePrefetcher(const FramePrefetcher&) = delete;
  FramePrefetcher& operator=(const FramePrefetcher&) = delete;

  // Moves the next frame into *frame; false once every frame has been taken.
  bool Next(SimFrame* frame);

 private:
  void Run();

  const Simulator& sim_;
  const size_t max_ahead_;
  const RenderFlags flags_;
  std::mutex mutex_;
  std::condition_variable changed_;
  std::deque<SimFrame> ready_;
  size_t taken_ = 0;
  bool stop_ = false;
  std::thread worker_;
};

}  // namespace icgm::sim
