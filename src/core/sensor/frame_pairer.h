// Pairs the colour and depth frames of an RGB-D sensor by their device stamps: each depth frame
// goes with the colour frame nearest in time, when they lie within max_dt_s of each other
// (half a frame period at 30 Hz by default). Frames that find no partner are dropped and
// counted. Used whether or not the device syncs its streams itself (it then only confirms the
// pairs).
#pragma once

#include <cstdint>
#include <deque>
#include <optional>

#include <opencv2/core.hpp>

#include "core/common/time.h"

namespace icgm {

struct StampedImage {
  uint64_t device_us = 0;  // the device's clock
  Time stamp;              // host time of the capture (DeviceClock)
  cv::Mat image;
};

struct RgbdPair {
  StampedImage color;
  StampedImage depth;
};

class FramePairer {
 public:
  explicit FramePairer(double max_dt_s = 0.0167, size_t max_queue = 4);

  // Adds a frame of one stream; returns the pair it completes, if any.
  std::optional<RgbdPair> AddColor(StampedImage frame);
  std::optional<RgbdPair> AddDepth(StampedImage frame);
  void Clear();

  size_t pairs() const { return pairs_; }
  size_t dropped() const { return dropped_; }

 private:
  // `frame` of one stream against the queue of the other; colour_first says which is which.
  std::optional<RgbdPair> Add(StampedImage frame, std::deque<StampedImage>* own,
                              std::deque<StampedImage>* other, bool frame_is_color);
  uint64_t max_dt_us_;
  size_t max_queue_;
  std::deque<StampedImage> color_;
  std::deque<StampedImage> depth_;
  size_t pairs_ = 0;
  size_t dropped_ = 0;
};

}  // namespace icgm
