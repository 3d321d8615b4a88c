// Ground-truth check of feature matches between two RGB-D frames: the first frame's keypoint,
// back-projected with its depth and moved by the ground-truth relative pose, must reproject
// onto the second frame's keypoint. Used to measure the matching precision of detectors on
// real sequences with motion-capture ground truth (TUM RGB-D).
#pragma once

#include <vector>

#include <opencv2/core.hpp>

#include "core/common/camera.h"
#include "core/common/pose.h"

namespace icgm {

// Per match (queryIdx in `a`, trainIdx in `b`): the pixel distance between b's keypoint and
// a's keypoint back-projected with depth_a_m (CV_32F metres, NaN or <= 0 invalid, read at the
// nearest pixel) and moved by b_from_a (T_b_a = T_world_b^-1 T_world_a). NaN when a's depth is
// invalid or the point falls behind camera b. Keypoints are pinhole pixels (no distortion).
std::vector<double> MatchReprojectionErrorsPx(const std::vector<cv::KeyPoint>& a,
                                              const std::vector<cv::KeyPoint>& b,
                                              const std::vector<cv::DMatch>& matches,
                                              const cv::Mat& depth_a_m,
                                              const CameraIntrinsics& intrinsics,
                                              const Pose3& b_from_a);

}  // namespace icgm
