#include "core/map/float_word_index.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>

namespace icgm {

FloatWordIndex::FloatWordIndex(int coarse_cells, int probe_cells)
    : coarse_cells_(std::max(1, coarse_cells)),
      probe_cells_(std::clamp(probe_cells, 1, std::max(1, coarse_cells))) {}

float FloatWordIndex::SquaredDistance(const float* a, const float* b) const {
  float s = 0.f;
  for (int i = 0; i < dims_; ++i) {
    const float d = a[i] - b[i];
    s += d * d;
  }
  return s;
}

std::vector<int> FloatWordIndex::NearestCells(const float* q, int count) const {
  std::vector<std::pair<float, int>> d;
  d.reserve(centroid_words_.size());
  for (size_t c = 0; c < centroid_words_.size(); ++c) {
    d.emplace_back(SquaredDistance(q, &words_[static_cast<size_t>(centroid_words_[c]) * dims_]),
                   static_cast<int>(c));
  }
  const int k = std::min<int>(count, static_cast<int>(d.size()));
  std::partial_sort(d.begin(), d.begin() + k, d.end());
  std::vector<int> out(k);
  for (int i = 0; i < k; ++i) out[i] = d[i].second;
  return out;
}

int FloatWordIndex::Nearest(const cv::Mat& row, double max_distance, double* distance) const {
  if (size_ == 0 || row.cols != dims_ || row.type() != CV_32FC1) return -1;
  const float* q = row.ptr<float>(0);
  int best = -1;
  float best_d2 = std::numeric_limits<float>::max();
  for (int c : NearestCells(q, probe_cells_)) {
    for (int w : cells_[c]) {
      const float d2 = SquaredDistance(q, &words_[static_cast<size_t>(w) * dims_]);
      if (d2 < best_d2) {
        best_d2 = d2;
        best = w;
      }
    }
  }
  if (best < 0 || std::sqrt(best_d2) > max_distance) return -1;
  if (distance) *distance = std::sqrt(best_d2);
  return best;
}

int FloatWordIndex::Add(const cv::Mat& row) {
  if (size_ == 0) dims_ = row.cols;
  const float* d = row.ptr<float>(0);
  words_.insert(words_.end(), d, d + dims_);
  const int id = size_++;
  if (static_cast<int>(centroid_words_.size()) < coarse_cells_) {
    centroid_words_.push_back(id);
    cells_.push_back({id});
  } else {
    cells_[NearestCells(d, 1).front()].push_back(id);
  }
  return id;
}

size_t FloatWordIndex::MemoryBytes() const {
  size_t bytes = words_.capacity() * sizeof(float) + centroid_words_.capacity() * sizeof(int);
  for (const auto& c : cells_) bytes += c.capacity() * sizeof(int) + sizeof(c);
  return bytes;
}

}  // namespace icgm
