// Keypoint positions bucketed in square cells, for the search around a projected point: every
// position within a radius of a pixel is visited without scanning the whole image. Cells are
// unbounded (positions outside the image, e.g. undistorted ones, keep their place).
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <unordered_map>
#include <vector>

#include <Eigen/Core>
#include <opencv2/core.hpp>

namespace icgm {

class KeypointGrid {
 public:
  // Position i enters the grid when `usable` is empty or usable[i] != 0. Cells of at least 4 px.
  KeypointGrid(std::vector<cv::Point2f> positions_px, const std::vector<uint8_t>& usable,
               double cell_px)
      : positions_(std::move(positions_px)), cell_(std::max(4.0, cell_px)) {
    for (size_t i = 0; i < positions_.size(); ++i) {
      if (!usable.empty() && !usable[i]) continue;
      cells_[Key(Cell(positions_[i].x), Cell(positions_[i].y))].push_back(static_cast<int>(i));
    }
  }

  // Calls f(i) for every position in the grid within `radius` of u: cells row by row, positions
  // in index order within a cell.
  template <typename F>
  void ForEachNear(const Eigen::Vector2d& u, double radius, F&& f) const {
    const int x0 = Cell(u.x() - radius), x1 = Cell(u.x() + radius);
    const int y0 = Cell(u.y() - radius), y1 = Cell(u.y() + radius);
    for (int cy = y0; cy <= y1; ++cy) {
      for (int cx = x0; cx <= x1; ++cx) {
        const auto it = cells_.find(Key(cx, cy));
        if (it == cells_.end()) continue;
        for (const int i : it->second) {
          const double dx = positions_[i].x - u.x(), dy = positions_[i].y - u.y();
          if (dx * dx + dy * dy <= radius * radius) f(i);
        }
      }
    }
  }

 private:
  int Cell(double v) const { return static_cast<int>(std::floor(v / cell_)); }
  static long long Key(int x, int y) {
    return (static_cast<long long>(x) << 32) ^ (y & 0xffffffffLL);
  }

  std::vector<cv::Point2f> positions_;
  double cell_;
  std::unordered_map<long long, std::vector<int>> cells_;
};

}  // namespace icgm
