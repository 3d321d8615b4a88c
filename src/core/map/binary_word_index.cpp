#include "core/map/binary_word_index.h"

#include <algorithm>
#include <cstring>
#include <limits>

namespace icgm {

namespace {

constexpr int kBucketsPerTable = 1 << 16;

// Hamming distance; kBytes > 0 fixes the width at compile time (32 for ORB / BRIEF), so the
// loop unrolls into four 64-bit popcounts.
template <int kBytes>
__attribute__((always_inline)) inline int HammingBits(const uint8_t* a, const uint8_t* b,
                                                      int bytes) {
  const int n = kBytes > 0 ? kBytes : bytes;
  int bits = 0;
  int i = 0;
  for (; i + 8 <= n; i += 8) {
    uint64_t x;
    uint64_t y;
    std::memcpy(&x, a + i, 8);
    std::memcpy(&y, b + i, 8);
    bits += __builtin_popcountll(x ^ y);
  }
  for (; i < n; ++i) bits += __builtin_popcount(static_cast<unsigned>(a[i] ^ b[i]));
  return bits;
}

}  // namespace

uint32_t BinaryWordIndex::Chunk(const uint8_t* d, int table) const {
  const int first = 2 * table;
  const uint32_t hi = d[first];
  const uint32_t lo = first + 1 < bytes_ ? d[first + 1] : 0u;
  return (hi << 8) | lo;
}

// always_inline: the body is compiled with the caller's target (POPCNT or baseline x86-64).
template <int kBytes>
__attribute__((always_inline)) inline void BinaryWordIndex::Scan(const uint8_t* q,
                                                                 uint64_t overfull, int good_enough,
                                                                 int* best, int* best_bits) const {
  for (size_t t = 0; t < tables_.size(); ++t) {
    const Table& table = tables_[t];
    const uint32_t key = Chunk(q, static_cast<int>(t));
    const uint32_t count = table.count[key];
    if (count == 0 || count > overfull) continue;
    // Only the newest block can be partly filled; its ids sit at the front.
    int in_block = count % kBlockIds == 0 ? kBlockIds : static_cast<int>(count % kBlockIds);
    for (int32_t b = table.head[key]; b >= 0; b = table.blocks[b].next, in_block = kBlockIds) {
      const Block& block = table.blocks[b];
      if (block.next >= 0) __builtin_prefetch(&table.blocks[block.next]);
      // The block's words lie scattered over the word array: fetch them all before comparing.
      for (int i = 0; i < in_block; ++i) {
        __builtin_prefetch(&words_[static_cast<size_t>(block.ids[i]) * bytes_]);
      }
      for (int i = 0; i < in_block; ++i) {
        const int32_t w = block.ids[i];
        const int bits = HammingBits<kBytes>(q, &words_[static_cast<size_t>(w) * bytes_], bytes_);
        if (bits < *best_bits || (bits == *best_bits && w < *best)) {
          *best_bits = bits;
          *best = w;
        }
      }
    }
    if (*best_bits <= good_enough) break;
  }
}

void BinaryWordIndex::ScanBaseline(const uint8_t* q, uint64_t overfull, int good_enough, int* best,
                                   int* best_bits) const {
  if (bytes_ == 32) {
    Scan<32>(q, overfull, good_enough, best, best_bits);
  } else {
    Scan<0>(q, overfull, good_enough, best, best_bits);
  }
}

#if defined(__x86_64__) && (defined(__GNUC__) || defined(__clang__))
__attribute__((target("popcnt"))) void BinaryWordIndex::ScanPopcnt(const uint8_t* q,
                                                                   uint64_t overfull,
                                                                   int good_enough, int* best,
                                                                   int* best_bits) const {
  if (bytes_ == 32) {
    Scan<32>(q, overfull, good_enough, best, best_bits);
  } else {
    Scan<0>(q, overfull, good_enough, best, best_bits);
  }
}

namespace {
bool HasPopcnt() {
  static const bool has = __builtin_cpu_supports("popcnt");
  return has;
}
}  // namespace
#endif

int BinaryWordIndex::Nearest(const cv::Mat& row, double max_distance, double* distance) const {
  if (size_ == 0 || row.cols != bytes_ || row.type() != CV_8UC1) return -1;
  const uint8_t* q = row.ptr<uint8_t>(0);
  const uint64_t overfull =
      static_cast<uint64_t>(kOverfullFactor) * (static_cast<uint64_t>(size_) / kBucketsPerTable) +
      kOverfullMinimum;
  const int good_enough = static_cast<int>(max_distance / 2);
  int best = -1;
  int best_bits = std::numeric_limits<int>::max();
#if defined(__x86_64__) && (defined(__GNUC__) || defined(__clang__))
  if (HasPopcnt()) {
    ScanPopcnt(q, overfull, good_enough, &best, &best_bits);
  } else {
    ScanBaseline(q, overfull, good_enough, &best, &best_bits);
  }
#else
  ScanBaseline(q, overfull, good_enough, &best, &best_bits);
#endif
  if (best < 0 || best_bits > max_distance) return -1;
  if (distance) *distance = best_bits;
  return best;
}

int BinaryWordIndex::Add(const cv::Mat& row) {
  if (size_ == 0) {
    bytes_ = row.cols;
    tables_.assign(static_cast<size_t>((bytes_ + 1) / 2), Table{});
    for (Table& t : tables_) {
      t.head.assign(kBucketsPerTable, -1);
      t.count.assign(kBucketsPerTable, 0);
    }
  }
  const uint8_t* d = row.ptr<uint8_t>(0);
  words_.insert(words_.end(), d, d + bytes_);
  const int id = size_++;
  for (size_t t = 0; t < tables_.size(); ++t) {
    Table& table = tables_[t];
    const uint32_t key = Chunk(d, static_cast<int>(t));
    const int slot = static_cast<int>(table.count[key] % kBlockIds);
    if (slot == 0) {
      Block block;
      block.next = table.head[key];
      table.head[key] = static_cast<int32_t>(table.blocks.size());
      table.blocks.push_back(block);
    }
    table.blocks[table.head[key]].ids[slot] = id;
    ++table.count[key];
  }
  return id;
}

size_t BinaryWordIndex::MemoryBytes() const {
  size_t bytes = words_.capacity();
  for (const auto& t : tables_) {
    bytes += t.head.capacity() * sizeof(int32_t) + t.count.capacity() * sizeof(uint32_t) +
             t.blocks.capacity() * sizeof(Block);
  }
  return bytes;
}

}  // namespace icgm
