// Multi-index hashing for binary words (Norouzi et al., "Fast Search in Hamming Space with
// Multi-Index Hashing", CVPR 2012, used here in its approximate single-probe form): each
// descriptor is cut into 16-bit substrings and every substring value keys one hash table. A query
// only compares (by popcount) the words that share at least one substring exactly. A word at
// Hamming distance d from the query with uniformly spread differing bits is found with
// probability 1 - (1 - (1 - d/B)^16)^(B/16) for B descriptor bits: 0.99 at d = 20 and 0.9 at
// d = 30 for 256-bit ORB, while unrelated words (d ~ B/2) collide with probability ~2^-16 per
// table. Two measures bound the cost on real, biased descriptor bits:
//  - buckets holding more than `kOverfullFactor` times the mean bucket load (substring values
//    that many unrelated descriptors share) are not scanned; the word is still reachable
//    through its other substrings;
//  - the scan stops at the first word within half the search radius (already the same word).
// Buckets are unrolled linked lists of 15-id blocks (64 bytes, one cache line): a scan waits for
// each block before it knows the next, so larger blocks mean fewer such waits (7-id blocks of
// half a line took ~1.5x the query time at 1,000 features per image).
#pragma once

#include <cstdint>
#include <vector>

#include "core/map/word_index.h"

namespace icgm {

class BinaryWordIndex : public WordIndex {
 public:
  int Nearest(const cv::Mat& row, double max_distance, double* distance) const override;
  int Add(const cv::Mat& row) override;
  int size() const override { return size_; }
  int dims() const override { return bytes_; }
  size_t MemoryBytes() const override;

 private:
  static constexpr int kBlockIds = 15;
  static constexpr int kOverfullFactor = 16;
  static constexpr int kOverfullMinimum = 28;  // buckets this full are always scanned
  struct alignas(64) Block {
    int32_t ids[kBlockIds];
    int32_t next;  // older block of the same bucket, or -1
  };
  struct Table {
    std::vector<int32_t> head;    // substring -> newest block, or -1
    std::vector<uint32_t> count;  // substring -> words in the bucket
    std::vector<Block> blocks;
  };

  uint32_t Chunk(const uint8_t* d, int table) const;
  // Scans the buckets of the query's substrings, table by table (see above), updating the
  // nearest word and its distance. Scan is instantiated for 32-byte words and any width;
  // ScanPopcnt is the same code compiled for the POPCNT instruction (chosen at run time).
  template <int kBytes>
  void Scan(const uint8_t* q, uint64_t overfull, int good_enough, int* best, int* best_bits) const;
  void ScanBaseline(const uint8_t* q, uint64_t overfull, int good_enough, int* best,
                    int* best_bits) const;
  void ScanPopcnt(const uint8_t* q, uint64_t overfull, int good_enough, int* best,
                  int* best_bits) const;

  int bytes_ = 0;
  int size_ = 0;
  std::vector<uint8_t> words_;  // size_ x bytes_
  std::vector<Table> tables_;
};

}  // namespace icgm
