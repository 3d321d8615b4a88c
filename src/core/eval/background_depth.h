// What moves in a sequence without masks, from its depth and ground-truth poses alone: the
// room's depth as the median of the depths other frames saw along each pixel's ray (people walk
// on and cover a pixel in fewer than half of the frames, the room stays), and the pixels whose
// depth lies clearly in front of it. Compares how much of
// the view walkers cover in a real sequence and a rendered one (whose masks check the measure).
#pragma once

#include <vector>

#include <opencv2/core.hpp>

#include "core/common/camera.h"
#include "core/common/pose.h"

namespace icgm {

// The background depth of a target frame (CV_32FC1 metres, 0 where fewer than min_sources
// source frames saw the ray): each source depth (CV_32FC1, NaN or <= 0 invalid; every
// stride_px-th pixel) is moved into the target by the poses (camera in world), the nearest kept
// per pixel (what that source would see there), then the median over the sources; finally the
// nearest within `spread_px`, so that a pose error of a pixel or two does not put an edge of
// the room in front of the wall behind it.
cv::Mat BackgroundDepth(const std::vector<cv::Mat>& source_depths_m,
                        const std::vector<Pose3>& T_world_source, const Pose3& T_world_target,
                        const CameraIntrinsics& intrinsics, int stride_px = 2, int spread_px = 2,
                        int min_sources = 3);

// Pixels with valid depth in front of the background by more than max(min_m, fraction x the
// background's depth), as a CV_8UC1 mask (255) of depth_m's size.
cv::Mat ForegroundMask(const cv::Mat& depth_m, const cv::Mat& background_m, double min_m = 0.3,
                       double fraction = 0.1);

}  // namespace icgm
