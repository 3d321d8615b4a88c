#include "core/map/binary_word_index.h"

#include <cstring>
#include <limits>

namespace icgm {

namespace {
constexpr int kBucketsPerTable = 1 << 16;
}  // namespace

uint32_t BinaryWordIndex::Chunk(const uint8_t* d, int table) const {
  const int first = 2 * table;
  const uint32_t hi = d[first];
  const uint32_t lo = first + 1 < bytes_ ? d[first + 1] : 0u;
  return (hi << 8) | lo;
}

int BinaryWordIndex::Hamming(const uint8_t* a, const uint8_t* b) const {
  int bits = 0;
  int i = 0;
  for (; i + 8 <= bytes_; i += 8) {
    uint64_t x;
    uint64_t y;
    std::memcpy(&x, a + i, 8);
    std::memcpy(&y, b + i, 8);
    bits += __builtin_popcountll(x ^ y);
  }
  for (; i < bytes_; ++i) bits += __builtin_popcount(static_cast<unsigned>(a[i] ^ b[i]));
  return bits;
}

int BinaryWordIndex::Nearest(const cv::Mat& row, double max_distance, double* distance) const {
  if (size_ == 0 || row.cols != bytes_ || row.type() != CV_8UC1) return -1;
  const uint8_t* q = row.ptr<uint8_t>(0);
  int best = -1;
  int best_bits = std::numeric_limits<int>::max();
  for (int t = 0; t < tables_; ++t) {
    for (int32_t w = heads_[t][Chunk(q, t)]; w >= 0; w = next_[t][w]) {
      const int bits = Hamming(q, &words_[static_cast<size_t>(w) * bytes_]);
      if (bits < best_bits || (bits == best_bits && w < best)) {
        best_bits = bits;
        best = w;
      }
    }
  }
  if (best < 0 || best_bits > max_distance) return -1;
  if (distance) *distance = best_bits;
  return best;
}

int BinaryWordIndex::Add(const cv::Mat& row) {
  if (size_ == 0) {
    bytes_ = row.cols;
    tables_ = (bytes_ + 1) / 2;
    heads_.assign(tables_, std::vector<int32_t>(kBucketsPerTable, -1));
    next_.assign(tables_, {});
  }
  const uint8_t* d = row.ptr<uint8_t>(0);
  words_.insert(words_.end(), d, d + bytes_);
  const int id = size_++;
  for (int t = 0; t < tables_; ++t) {
    int32_t& head = heads_[t][Chunk(d, t)];
    next_[t].push_back(head);
    head = id;
  }
  return id;
}

size_t BinaryWordIndex::MemoryBytes() const {
  size_t bytes = words_.capacity();
  for (const auto& h : heads_) bytes += h.capacity() * sizeof(int32_t);
  for (const auto& n : next_) bytes += n.capacity() * sizeof(int32_t);
  return bytes;
}

}  // namespace icgm
