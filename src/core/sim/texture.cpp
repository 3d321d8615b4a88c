#include "core/sim/texture.h"

#include <algorithm>
#include <cassert>

#include <opencv2/imgproc.hpp>

namespace icgm::sim {

Texture::Texture(const cv::Mat& bgr, double texel_size_m)
    : inv_texel_m_(static_cast<float>(1.0 / texel_size_m)) {
  assert(!bgr.empty() && bgr.type() == CV_8UC3 && texel_size_m > 0);
  levels_.push_back(bgr.isContinuous() ? bgr : bgr.clone());
  level_scale_.push_back(1.0f);
  // Halve until the smaller side would drop below 8 texels.
  while (std::min(levels_.back().cols, levels_.back().rows) >= 16 && levels_.size() < 8) {
    cv::Mat next;
    cv::resize(levels_.back(), next,
               cv::Size((levels_.back().cols + 1) / 2, (levels_.back().rows + 1) / 2), 0, 0,
               cv::INTER_AREA);
    levels_.push_back(next);
    level_scale_.push_back(level_scale_.back() * 0.5f);
  }
}

}  // namespace icgm::sim
