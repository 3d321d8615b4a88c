// Inverted-file index for float words (L2): the first `coarse_cells` words added become fixed
// coarse centroids, every word is filed under its nearest centroid, and a query scans the words of
// its `probe_cells` nearest cells. Needs no offline training, which keeps the dictionary fully
// online-incremental (thesis 4.2); approximate when probe_cells < coarse_cells.
#pragma once

#include <vector>

#include "core/map/word_index.h"

namespace icgm {

class FloatWordIndex : public WordIndex {
 public:
  FloatWordIndex(int coarse_cells, int probe_cells);
  int Nearest(const cv::Mat& row, double max_distance, double* distance) const override;
  int Add(const cv::Mat& row) override;
  int size() const override { return size_; }
  int dims() const override { return dims_; }
  size_t MemoryBytes() const override;

 private:
  float SquaredDistance(const float* a, const float* b) const;
  std::vector<int> NearestCells(const float* q, int count) const;

  int coarse_cells_;
  int probe_cells_;
  int dims_ = 0;
  int size_ = 0;
  std::vector<float> words_;             // size_ x dims_
  std::vector<int> centroid_words_;      // word id of each centroid
  std::vector<std::vector<int>> cells_;  // centroid -> word ids
};

}  // namespace icgm
