// Synthetic places for dictionary and loop-closure tests: each place owns a fixed set of random
// binary descriptors (ORB-like, 32 bytes); a view of the place re-observes most of them with a
// few flipped bits, as a revisit under noise would.
#pragma once

#include <random>
#include <vector>

#include <opencv2/core.hpp>

namespace icgm::test {

class SyntheticPlaces {
 public:
  SyntheticPlaces(int places, int features_per_place, unsigned seed)
      : rng_(seed), places_(static_cast<size_t>(places)) {
    std::uniform_int_distribution<int> byte(0, 255);
    for (auto& p : places_) {
      p.create(features_per_place, 32, CV_8U);
      for (int r = 0; r < p.rows; ++r) {
        for (int c = 0; c < p.cols; ++c) p.at<uint8_t>(r, c) = static_cast<uint8_t>(byte(rng_));
      }
    }
  }

  // A view of `place`: keeps each descriptor with probability `keep`, flips `flipped_bits`.
  cv::Mat View(int place, double keep, int flipped_bits) {
    const cv::Mat& src = places_.at(static_cast<size_t>(place));
    std::bernoulli_distribution keep_it(keep);
    std::uniform_int_distribution<int> bit(0, 255);
    cv::Mat out;
    for (int r = 0; r < src.rows; ++r) {
      if (!keep_it(rng_)) continue;
      cv::Mat row = src.row(r).clone();
      for (int b = 0; b < flipped_bits; ++b) {
        const int k = bit(rng_);
        row.at<uint8_t>(0, k / 8) ^= static_cast<uint8_t>(1u << (k % 8));
      }
      out.push_back(row);
    }
    return out;
  }

 private:
  std::mt19937 rng_;
  std::vector<cv::Mat> places_;
};

}  // namespace icgm::test
