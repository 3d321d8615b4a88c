#include "core/dataset/depth_buffers.h"

namespace icgm {

namespace {

// Only the pool refers to `m`: no frame or keyframe reads it any more.
bool Unused(const cv::Mat& m) { return m.u != nullptr && CV_XADD(&m.u->refcount, 0) == 1; }

}  // namespace

cv::Mat DepthBuffers::Take(int rows, int cols) {
  for (cv::Mat& b : buffers_) {
    if (!Unused(b)) continue;
    if (b.rows != rows || b.cols != cols) b.create(rows, cols, CV_32FC1);  // another camera
    return b;
  }
  cv::Mat fresh(rows, cols, CV_32FC1);
  if (buffers_.size() < capacity_) buffers_.push_back(fresh);
  return fresh;
}

}  // namespace icgm
