// BinaryWordIndex::Nearest against a plain re-statement of its search rule (binary_word_index.h)
// that scans every word: tables in order, only the words sharing the table's 16-bit substring
// with the query, buckets holding more than 16 x (words / 65536) + 28 words skipped, nearest by
// (distance, id), and the search ends after the first table whose best is within half the
// radius. The fast scan (popcount dispatch, unrolled widths, prefetching) must give exactly the
// same word and distance for every query.
#include "core/map/binary_word_index.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <limits>
#include <random>
#include <vector>

namespace icgm {
namespace {

struct Reference {
  std::vector<cv::Mat> words;

  static uint32_t Chunk(const cv::Mat& d, int table) {
    const int first = 2 * table;
    const uint32_t hi = d.at<uint8_t>(0, first);
    const uint32_t lo = first + 1 < d.cols ? d.at<uint8_t>(0, first + 1) : 0u;
    return (hi << 8) | lo;
  }

  int Nearest(const cv::Mat& q, double max_distance, int* bits_out) const {
    const int tables = (q.cols + 1) / 2;
    const size_t overfull = 16 * (words.size() / 65536) + 28;
    const int good_enough = static_cast<int>(max_distance / 2);
    int best = -1;
    int best_bits = std::numeric_limits<int>::max();
    for (int t = 0; t < tables; ++t) {
      std::vector<int> bucket;
      for (size_t w = 0; w < words.size(); ++w) {
        if (Chunk(words[w], t) == Chunk(q, t)) bucket.push_back(static_cast<int>(w));
      }
      if (bucket.empty() || bucket.size() > overfull) continue;
      for (int w : bucket) {
        const int bits = static_cast<int>(cv::norm(q, words[w], cv::NORM_HAMMING));
        if (bits < best_bits || (bits == best_bits && w < best)) {
          best_bits = bits;
          best = w;
        }
      }
      if (best_bits <= good_enough) break;
    }
    if (best < 0 || best_bits > max_distance) return -1;
    *bits_out = best_bits;
    return best;
  }
};

cv::Mat Flip(const cv::Mat& d, int bits, std::mt19937* rng) {
  cv::Mat out = d.clone();
  std::uniform_int_distribution<int> bit(0, d.cols * 8 - 1);
  for (int i = 0; i < bits; ++i) {
    const int b = bit(*rng);
    out.at<uint8_t>(0, b / 8) ^= static_cast<uint8_t>(1u << (b % 8));
  }
  return out;
}

cv::Mat Random(int bytes, std::mt19937* rng) {
  cv::Mat d(1, bytes, CV_8U);
  for (int c = 0; c < bytes; ++c) d.at<uint8_t>(0, c) = static_cast<uint8_t>((*rng)());
  return d;
}

void CheckAgainstReference(int bytes, int centers, int per_center, int queries) {
  std::mt19937 rng(17 + bytes);
  BinaryWordIndex index;
  Reference reference;
  std::vector<cv::Mat> center;
  for (int c = 0; c < centers; ++c) center.push_back(Random(bytes, &rng));
  std::uniform_int_distribution<int> flips(0, std::max(2, 30 * bytes / 32));  // 30 of 256 bits
  auto add = [&](const cv::Mat& d) {
    EXPECT_EQ(index.Add(d), static_cast<int>(reference.words.size()));
    reference.words.push_back(d);
  };
  for (int c = 0; c < centers; ++c) {
    for (int k = 0; k < per_center; ++k) add(Flip(center[c], flips(rng), &rng));
  }
  // 80 words sharing their first two bytes: an overfull bucket in table 0.
  for (int k = 0; k < 80; ++k) {
    cv::Mat d = Random(bytes, &rng);
    d.at<uint8_t>(0, 0) = 0xA5;
    d.at<uint8_t>(0, 1) = 0x3C;
    add(d);
  }
  std::uniform_int_distribution<int> pick(0, centers - 1);
  int found = 0, missed = 0;
  for (int i = 0; i < queries; ++i) {
    // Near stored words, a new place, or a query landing in the overfull bucket of table 0.
    cv::Mat q = i % 3 == 0 ? Flip(center[pick(rng)], flips(rng), &rng) : Random(bytes, &rng);
    if (i % 3 == 2) {
      q.at<uint8_t>(0, 0) = 0xA5;
      q.at<uint8_t>(0, 1) = 0x3C;
    }
    for (double radius : {40.0, 64.0}) {
      int ref_bits = -1;
      const int ref = reference.Nearest(q, radius, &ref_bits);
      double bits = -1.0;
      const int got = index.Nearest(q, radius, &bits);
      ASSERT_EQ(got, ref) << "query " << i << " radius " << radius;
      if (ref >= 0) {
        EXPECT_EQ(static_cast<int>(bits), ref_bits) << "query " << i;
      }
      (ref >= 0 ? found : missed) += 1;
    }
  }
  // Both outcomes occur, so the comparison covers hits and misses.
  EXPECT_GT(found, queries / 4);
  EXPECT_GT(missed, queries / 4);
}

TEST(BinaryWordIndexTest, NearestFollowsItsSearchRuleFor32ByteWords) {
  CheckAgainstReference(32, 400, 5, 600);
}

TEST(BinaryWordIndexTest, NearestFollowsItsSearchRuleForOtherWidths) {
  CheckAgainstReference(61, 150, 4, 300);  // AKAZE's 486-bit descriptors
  CheckAgainstReference(8, 150, 4, 300);
}

}  // namespace
}  // namespace icgm
