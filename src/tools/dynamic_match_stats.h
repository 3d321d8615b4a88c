// How many of the matches used for registration lie on moving objects, measured with the
// simulator's per-pixel ground-truth dynamic mask (255 = pedestrian is the visible surface).
// Counts the current-frame side of each 2-D match given to RegisterRgbd and of its RANSAC
// inliers; the share over a sequence is the figure that shows what ICGM removes.
#pragma once

#include <cstddef>
#include <vector>

#include <opencv2/core.hpp>

namespace icgm::tools {

struct DynamicMatchCount {
  size_t matches = 0;          // 2-D matches given to registration
  size_t dynamic_matches = 0;  // ... whose current-frame pixel is on the mask
  size_t inliers = 0;          // RANSAC inliers among them
  size_t dynamic_inliers = 0;  // ... on the mask

  DynamicMatchCount& operator+=(const DynamicMatchCount& o);
  double MatchShare() const { return matches ? double(dynamic_matches) / matches : 0.0; }
  double InlierShare() const { return inliers ? double(dynamic_inliers) / inliers : 0.0; }
};

// `mask`: CV_8UC1, non-zero on moving objects; `inlier_indices` index into `pixels`.
// Pixels outside the image count as static.
DynamicMatchCount CountDynamicMatches(const cv::Mat& mask, const std::vector<cv::Point2f>& pixels,
                                      const std::vector<int>& inlier_indices);

}  // namespace icgm::tools
