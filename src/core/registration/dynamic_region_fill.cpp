#include "core/registration/dynamic_region_fill.h"

#include <cmath>
#include <deque>

namespace icgm {

cv::Mat FillConnectedSurface(const cv::Mat& seeds, const cv::Mat& depth_m, int step_px,
                             const SurfaceFillOptions& o) {
  cv::Mat out = seeds.clone();
  if (seeds.empty() || o.max_step_m <= 0.0 || depth_m.empty() || depth_m.type() != CV_32FC1 ||
      step_px < 1) {
    return out;
  }
  const auto cell_depth = [&](int gv, int gu) {
    const int v = gv * step_px, u = gu * step_px;
    if (v >= depth_m.rows || u >= depth_m.cols) return std::nanf("");
    const float z = depth_m.at<float>(v, u);
    return std::isfinite(z) && z >= o.min_depth_m && z <= o.max_depth_m ? z : std::nanf("");
  };
  struct Cell {
    int gv, gu;
    float seed_z;
  };
  std::deque<Cell> open;
  for (int gv = 0; gv < out.rows; ++gv) {
    for (int gu = 0; gu < out.cols; ++gu) {
      if (!out.at<uint8_t>(gv, gu)) continue;
      out.at<uint8_t>(gv, gu) = 255;
      const float z = cell_depth(gv, gu);
      if (std::isfinite(z)) open.push_back({gv, gu, z});
    }
  }
  constexpr int kDv[4] = {-1, 1, 0, 0}, kDu[4] = {0, 0, -1, 1};
  while (!open.empty()) {
    const Cell c = open.front();
    open.pop_front();
    const float z = cell_depth(c.gv, c.gu);
    for (int n = 0; n < 4; ++n) {
      const int gv = c.gv + kDv[n], gu = c.gu + kDu[n];
      if (gv < 0 || gu < 0 || gv >= out.rows || gu >= out.cols || out.at<uint8_t>(gv, gu)) {
        continue;
      }
      const float zn = cell_depth(gv, gu);
      if (!std::isfinite(zn) || std::abs(zn - z) > o.max_step_m ||
          std::abs(zn - c.seed_z) > o.band_m) {
        continue;
      }
      out.at<uint8_t>(gv, gu) = 255;
      open.push_back({gv, gu, c.seed_z});
    }
  }
  return out;
}

}  // namespace icgm
