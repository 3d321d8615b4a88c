// Nearest-word search for the incremental visual dictionary. Words are only ever appended
// (PIRF-nav 2.0 style online dictionary), so indexes are built incrementally, never retrained.
// Descriptor type is a policy: Hamming distance on CV_8U rows, L2 on CV_32F rows.
#pragma once

#include <cstddef>
#include <memory>

#include <opencv2/core.hpp>

namespace icgm {

struct WordIndexOptions {
  bool binary = true;
  // Float index: the first `coarse_cells` words become fixed coarse centroids (an inverted-file
  // quantizer that needs no training pass); a query probes its `probe_cells` nearest cells.
  int coarse_cells = 256;
  int probe_cells = 8;
};

class WordIndex {
 public:
  virtual ~WordIndex() = default;
  static std::unique_ptr<WordIndex> Create(const WordIndexOptions& options);

  // Nearest stored word to `row` (1 x dims, same type as the words) with distance <= max_distance
  // (bits for binary, L2 for float), or -1. Approximate: may miss a word a linear scan would find.
  virtual int Nearest(const cv::Mat& row, double max_distance, double* distance) const = 0;
  // Appends `row` as word number size(); returns its id.
  virtual int Add(const cv::Mat& row) = 0;
  virtual int size() const = 0;
  // Descriptor width in columns (0 before the first word).
  virtual int dims() const = 0;
  virtual size_t MemoryBytes() const = 0;
};

}  // namespace icgm
