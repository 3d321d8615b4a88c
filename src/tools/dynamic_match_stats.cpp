#include "tools/dynamic_match_stats.h"

#include <cmath>

namespace icgm::tools {

namespace {
bool OnMask(const cv::Mat& mask, const cv::Point2f& p) {
  const int x = static_cast<int>(std::lround(p.x));
  const int y = static_cast<int>(std::lround(p.y));
  if (x < 0 || y < 0 || x >= mask.cols || y >= mask.rows) return false;
  return mask.at<uint8_t>(y, x) != 0;
}
}  // namespace

DynamicMatchCount& DynamicMatchCount::operator+=(const DynamicMatchCount& o) {
  matches += o.matches;
  dynamic_matches += o.dynamic_matches;
  inliers += o.inliers;
  dynamic_inliers += o.dynamic_inliers;
  return *this;
}

DynamicMatchCount CountDynamicMatches(const cv::Mat& mask, const std::vector<cv::Point2f>& pixels,
                                      const std::vector<int>& inlier_indices) {
  DynamicMatchCount c;
  if (mask.empty() || mask.type() != CV_8UC1) return c;
  c.matches = pixels.size();
  for (const cv::Point2f& p : pixels) c.dynamic_matches += OnMask(mask, p);
  for (int i : inlier_indices) {
    if (i < 0 || static_cast<size_t>(i) >= pixels.size()) continue;
    ++c.inliers;
    c.dynamic_inliers += OnMask(mask, pixels[i]);
  }
  return c;
}

}  // namespace icgm::tools
