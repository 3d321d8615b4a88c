// SURF keypoints and 64-D descriptors (Bay et al., ECCV 2006 / CVIU 2008), the project's own
// implementation: fast-Hessian detection (fast_hessian.h) and the Haar-wavelet orientation and
// descriptor (surf_descriptor.h) on one integral image. Upright (U-SURF) skips the orientation,
// for cameras that do not roll (the thesis's robot-mounted Kinect).
#pragma once

#include <vector>

#include <opencv2/core.hpp>

#include "core/features/fast_hessian.h"

namespace icgm {

struct SurfOptions {
  FastHessianOptions detector;
  bool upright = false;
  // At most this many keypoints (the largest determinants) are described; <= 0: all.
  int max_keypoints = 1000;
};

// Keypoints of an 8-bit gray image with one CV_32F row of 64 values per keypoint. KeyPoint
// fields: pt (pixels), size = interpolated box-filter side L in pixels (Gaussian scale
// s = 1.2 L / 9), angle in degrees [0, 360) in the image frame (0 when upright), response =
// determinant of the Hessian, octave = scale-space octave, class_id = sign of the Laplacian.
// `buffers` (optional, not shared between threads) keeps the integral image and the response
// layers between calls; the result does not depend on it.
struct SurfBuffers {
  cv::Mat integral;
  FastHessianBuffers hessian;
};
void ExtractSurf(const cv::Mat& gray, const SurfOptions& options,
                 std::vector<cv::KeyPoint>* keypoints, cv::Mat* descriptors,
                 SurfBuffers* buffers = nullptr);

// Gaussian scale s of a keypoint made by ExtractSurf.
inline double SurfScale(const cv::KeyPoint& keypoint) { return 1.2 * keypoint.size / 9.0; }

}  // namespace icgm
