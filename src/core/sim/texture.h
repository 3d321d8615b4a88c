// A surface texture in metric coordinates with a mip pyramid, so a surface seen from far away
// is sampled at a resolution matching the pixel footprint (little aliasing, stable features).
#pragma once

#include <cmath>
#include <cstdint>
#include <vector>

#include <opencv2/core.hpp>

namespace icgm::sim {

class Texture {
 public:
  // `bgr` (CV_8UC3, non-empty) covers texel_size_m per texel; coordinates wrap around.
  Texture(const cv::Mat& bgr, double texel_size_m);

  // Writes the colour at surface coordinates (u_m right, v_m down) in metres, for a pixel
  // whose footprint on the surface is footprint_m wide.
  void Sample(float u_m, float v_m, float footprint_m, uint8_t* bgr) const {
    int level = 0;
    float ratio = footprint_m * inv_texel_m_;
    const int last = static_cast<int>(levels_.size()) - 1;
    while (ratio >= 2.0f && level < last) {
      ratio *= 0.5f;
      ++level;
    }
    const cv::Mat& img = levels_[level];
    const float scale = inv_texel_m_ * level_scale_[level];
    int x = static_cast<int>(std::floor(u_m * scale)) % img.cols;
    int y = static_cast<int>(std::floor(v_m * scale)) % img.rows;
    if (x < 0) x += img.cols;
    if (y < 0) y += img.rows;
    const uint8_t* p = img.ptr<uint8_t>(y) + 3 * x;
    bgr[0] = p[0];
    bgr[1] = p[1];
    bgr[2] = p[2];
  }

  double width_m() const { return levels_[0].cols / inv_texel_m_; }
  double height_m() const { return levels_[0].rows / inv_texel_m_; }
  const cv::Mat& image() const { return levels_[0]; }

 private:
  std::vector<cv::Mat> levels_;
  std::vector<float> level_scale_;  // 2^-level
  float inv_texel_m_;
};

}  // namespace icgm::sim
