// Exhaustive two-nearest-neighbour search under Hamming distance for binary descriptors
// (ORB/BRIEF 32 bytes, AKAZE MLDB 61 bytes, any width). Rows are compared 64 bits at a time
// with a population count; the hardware POPCNT instruction is used when the CPU has it
// (checked at run time), which is several times faster than cv::BFMatcher with NORM_HAMMING on
// a baseline x86-64 build of OpenCV. 32-byte rows on a CPU with AVX2 are compared eight train
// rows at a time (a byte-wise count by nibble table), with the same result.
#pragma once

#include <vector>

#include <opencv2/core.hpp>

namespace icgm {

struct HammingKnn2 {
  int best = -1;          // train row of the nearest neighbour, -1 when train is empty
  int best_distance = 0;  // bits
  // Distance of the second nearest neighbour; INT_MAX when train has a single row.
  int second_distance = 0;
};

// For each row of `query` (CV_8UC1, same width as `train`), its nearest and second nearest
// rows of `train`. Ties keep the lower train index. Returns false (and clears `out`) for
// mismatched or non-CV_8UC1 inputs.
bool HammingKnn2Search(const cv::Mat& query, const cv::Mat& train, std::vector<HammingKnn2>* out);

}  // namespace icgm
