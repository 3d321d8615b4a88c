#include "core/mono/mono_input_queue.h"

#include <utility>

namespace icgm {

void MonoInputQueue::AddImage(Time stamp, cv::Mat image) {
  MonoInput input;
  input.stamp = stamp;
  input.image = std::move(image);
  images_.push_back(std::move(input));
  ++images_since_wheel_;
}

void MonoInputQueue::AddWheel(Time stamp, const Pose3& odom_base) {
  if (!wheels_) return;
  wheel_.push_back({stamp, odom_base});
  images_since_wheel_ = 0;
}

bool MonoInputQueue::Pop(MonoInput* input) {
  if (images_.empty()) return false;
  const Time stamp = images_.front().stamp;
  if (wheels_) {
    const bool covered = !wheel_.empty() && wheel_.back().stamp >= stamp;
    if (!covered && images_since_wheel_ <= max_wait_images_) return false;
  }
  *input = std::move(images_.front());
  images_.pop_front();
  input->wheel.clear();
  while (!wheel_.empty() && wheel_.front().stamp <= stamp) {
    input->wheel.push_back(wheel_.front());
    wheel_.pop_front();
  }
  return true;
}

size_t MonoInputQueue::DropImages() {
  const size_t n = images_.size();
  images_.clear();
  return n;
}

}  // namespace icgm
