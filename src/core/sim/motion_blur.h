// Motion blur of the colour image from the camera's motion during the exposure: each pixel
// becomes the mean of the rendered image along the path its surface point (at the rendered
// depth) takes across the image while the camera moves. Walkers are blurred as if they stood
// still; their own motion is not added.
#pragma once

#include <opencv2/core.hpp>

#include "core/common/camera.h"
#include "core/common/pose.h"

namespace icgm::sim {

// `bgr` (CV_8UC3) and `depth_m` (CV_32FC1, > 0 everywhere, the ideal depth) are rendered at the
// middle of the exposure; T_mid_start and T_mid_end are the camera's poses at the exposure's
// start and end in the middle pose's frame. Pixels move along start -> middle -> end; each
// output pixel averages up to max_samples samples of that path (one per pixel of its length).
void ApplyMotionBlur(const CameraIntrinsics& intrinsics, const cv::Mat& depth_m,
                     const Pose3& T_mid_start, const Pose3& T_mid_end, cv::Mat* bgr,
                     int max_samples = 24);

}  // namespace icgm::sim
