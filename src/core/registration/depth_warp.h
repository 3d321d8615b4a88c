// Re-renders a metric depth image as a camera at a nearby pose would have seen it. Used to bring
// a depth image to the instant of its colour image when the two were captured at different
// times (Kinect v1: colour and depth run unsynchronized, up to half a frame apart) while the
// camera moved: keypoints found in the colour image then get the depth of the same instant.
//
// For each target pixel u the source depth is looked up where the target ray's point appears in
// the source camera (fixed-point iteration starting from the source depth at u itself), and the
// point is carried into the target frame. Nearest-pixel lookups keep depth edges sharp (no
// mixing of foreground and background). Pixels whose point leaves the source image or has no
// source depth become NaN.
#pragma once

#include <vector>

#include <opencv2/core.hpp>

#include "core/common/camera.h"
#include "core/common/pose.h"

namespace icgm {

// `depth_m`: CV_32FC1 metres (NaN or <= 0: no measurement), of the intrinsics' size.
// `target_from_source`: p_target = target_from_source * p_source. Returns a new CV_32FC1 image
// (NaN where unknown); an identity pose returns a copy with invalid values as NaN.
cv::Mat WarpDepthImage(const cv::Mat& depth_m, const CameraIntrinsics& intrinsics,
                       const Pose3& target_from_source, int iterations = 2);

// The same with one pose per source row (rolling shutter: each row captured at its own instant):
// `target_from_source_row[v]` carries points of source row v into the target frame; its size is
// the image's row count.
cv::Mat WarpDepthImageByRow(const cv::Mat& depth_m, const CameraIntrinsics& intrinsics,
                            const std::vector<Pose3>& target_from_source_row, int iterations = 2);

}  // namespace icgm
