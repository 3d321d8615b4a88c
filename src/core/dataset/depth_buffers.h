// Metric depth images of a live stream, reused: a frame's CV_32FC1 depth (1.2 MB at VGA) goes
// into a buffer nothing refers to any more (its frame processed, its keyframe replaced) instead
// of a new allocation, which the allocator would fault in page by page and give back to the
// system every frame. Buffers still referred to (a queued frame, the front end's keyframes) are
// never handed out; beyond `capacity` buffers in use, a new image is allocated and not kept.
// Not thread-safe: one caller at a time (the buffers' reference counts are atomic, so the front
// end may release them on any thread).
#pragma once

#include <cstddef>
#include <vector>

#include <opencv2/core.hpp>

namespace icgm {

class DepthBuffers {
 public:
  explicit DepthBuffers(size_t capacity = 8) : capacity_(capacity) {}
  // A CV_32FC1 rows x cols image nothing else refers to; its pixels are undefined.
  cv::Mat Take(int rows, int cols);
  size_t size() const { return buffers_.size(); }

 private:
  size_t capacity_;
  std::vector<cv::Mat> buffers_;
};

}  // namespace icgm
