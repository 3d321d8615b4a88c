#include "core/sensor/frame_pairer.h"

#include <cmath>
#include <utility>

namespace icgm {

namespace {
uint64_t AbsDiff(uint64_t a, uint64_t b) { return a > b ? a - b : b - a; }
}  // namespace

FramePairer::FramePairer(double max_dt_s, size_t max_queue)
    : max_dt_us_(static_cast<uint64_t>(std::llround(max_dt_s * 1e6))),
      max_queue_(max_queue < 1 ? 1 : max_queue) {}

std::optional<RgbdPair> FramePairer::AddColor(StampedImage frame) {
  return Add(std::move(frame), &color_, &depth_, true);
}

std::optional<RgbdPair> FramePairer::AddDepth(StampedImage frame) {
  return Add(std::move(frame), &depth_, &color_, false);
}

void FramePairer::Clear() {
  color_.clear();
  depth_.clear();
}

std::optional<RgbdPair> FramePairer::Add(StampedImage frame, std::deque<StampedImage>* own,
                                         std::deque<StampedImage>* other, bool frame_is_color) {
  // Frames of this stream older than the new one can no longer be nearer to a later partner.
  size_t best = other->size();
  uint64_t best_dt = 0;
  for (size_t i = 0; i < other->size(); ++i) {
    const uint64_t dt = AbsDiff((*other)[i].device_us, frame.device_us);
    if (best == other->size() || dt < best_dt) {
      best = i;
      best_dt = dt;
    }
  }
  if (best < other->size() && best_dt <= max_dt_us_) {
    RgbdPair pair;
    StampedImage partner = std::move((*other)[best]);
    dropped_ += best;  // older frames of the other stream found no partner
    other->erase(other->begin(), other->begin() + static_cast<long>(best) + 1);
    dropped_ += own->size();
    own->clear();
    if (frame_is_color) {
      pair.color = std::move(frame);
      pair.depth = std::move(partner);
    } else {
      pair.color = std::move(partner);
      pair.depth = std::move(frame);
    }
    ++pairs_;
    return pair;
  }
  own->push_back(std::move(frame));
  while (own->size() > max_queue_) {
    own->pop_front();
    ++dropped_;
  }
  return std::nullopt;
}

}  // namespace icgm
