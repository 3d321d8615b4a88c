// A downsampled copy of a keyframe's depth and colour images, kept in the map (optional, see
// MapOptions::store_depth_images) so dense map products (a coloured point cloud, an occupancy
// grid) can be built later and points on walkers can be checked against other keyframes.
//
// Stored pixel (u, v) is the full image's pixel (u * f + f / 2, v * f + f / 2) for the
// downsampling factor f (a subsample, not an average: depth edges stay sharp and the pixel keeps
// the identity of the full image's pixel). `intrinsics` describe the stored images, so
// BackProject / Project work on them directly.
#pragma once

#include <opencv2/core.hpp>

#include "core/common/camera.h"

namespace icgm {

struct KeyframeImages {
  cv::Mat depth_mm;  // CV_16UC1 millimetres, 0 = no depth
  cv::Mat bgr;       // CV_8UC3 of the same size, or empty (no colour)
  CameraIntrinsics intrinsics;  // of the stored images
  int downsample = 1;

  bool empty() const { return depth_mm.empty(); }
  // Depth in metres at stored pixel (u, v); 0 where there is none or outside the image.
  double DepthM(int u, int v) const {
    if (u < 0 || v < 0 || u >= depth_mm.cols || v >= depth_mm.rows) return 0.0;
    return depth_mm.at<uint16_t>(v, u) * 1e-3;
  }
  // The full image's pixel of stored pixel (u, v).
  cv::Point2f FullPixel(int u, int v) const {
    const int offset = downsample / 2;
    return {static_cast<float>(u * downsample + offset), static_cast<float>(v * downsample + offset)};
  }
};

// Subsamples `depth_m` (CV_32FC1 metres, NaN / 0 / negative = none) and `bgr` (CV_8UC3, may be
// empty) of a camera `intrinsics` by `factor` >= 1. Depths beyond 65.5 m are dropped.
KeyframeImages DownsampleKeyframeImages(const cv::Mat& bgr, const cv::Mat& depth_m,
                                        const CameraIntrinsics& intrinsics, int factor);

}  // namespace icgm
