// How well a sequence's static-scene ("room") keypoints come back in a later frame, judged by the
// ground-truth motion: each room keypoint of frame a, back-projected with its depth and moved by
// the true relative pose, lands at a pixel of frame b; is a keypoint detected there (detector
// repeatability), and does descriptor matching pick one there (match precision, and how close)?
// The same measure on a real sequence (room = beyond a depth where people do not stand) and a
// rendered one (room = outside the walkers' masks as well) tells whether the rendered room's
// keypoints are more repeatable or more precise than the real room's.
//
// A real ground truth (motion capture, stamps) can be off by a common image shift of a pixel or
// two between two frames; errors are therefore also measured after removing each pair's common
// shift (the median offset of the matches lying near their true reprojection), so that the
// keypoints' own precision is compared, not the ground truth's.
#pragma once

#include <vector>

#include <Eigen/Core>
#include <opencv2/core.hpp>

#include "core/common/camera.h"
#include "core/common/pose.h"

namespace icgm {

struct KeypointRepeatabilityOptions {
  // Room keypoints: depth at least this (people nearer stand in front of the room); 0 keeps
  // every depth (use with masks).
  double min_depth_m = 2.5;
  // The reprojected point counts as visible in b when b's depth there agrees with its predicted
  // depth within this fraction (not hidden by something that stepped in front).
  double visible_depth_fraction = 0.1;
  // Reprojections closer than this to the image border are not counted.
  double border_px = 8.0;
  // Matches within this of their true reprojection estimate the pair's common shift.
  double shift_search_px = 10.0;
  // A match is correct within this of its true reprojection (after removing the common shift).
  double correct_px = 3.0;
};

struct KeypointRepeatabilityStats {
  int room_keypoints = 0;  // a's room keypoints whose reprojection is visible in b
  // Of those, with any b keypoint within 1 / 2 px of the reprojection (after the common shift).
  int repeated_1px = 0;
  int repeated_2px = 0;
  int matched = 0;          // of those, with a descriptor match into b
  int matched_correct = 0;  // of the matched, within correct_px (after the common shift)
  // Errors of the correct matches after / before removing the common shift [px].
  std::vector<double> correct_errors_px;
  std::vector<double> raw_errors_px;
  // The pair's common shift (median of b keypoint minus reprojection over the matches within
  // shift_search_px; zero without any) and how many matches estimated it.
  Eigen::Vector2d common_shift_px = Eigen::Vector2d::Zero();
  int shift_support = 0;
};

// a, b: keypoints (pinhole pixels) of two frames; depth_*_m: CV_32FC1 metres (NaN or <= 0
// invalid); mask_*: CV_8UC1 non-zero where something moves (empty: no mask); matches: a (query)
// to b (train), e.g. DescriptorMatcher's; b_from_a = T_world_b^-1 T_world_a (ground truth).
KeypointRepeatabilityStats MeasureKeypointRepeatability(
    const std::vector<cv::KeyPoint>& a, const cv::Mat& depth_a_m, const cv::Mat& mask_a,
    const std::vector<cv::KeyPoint>& b, const cv::Mat& depth_b_m, const cv::Mat& mask_b,
    const std::vector<cv::DMatch>& matches, const CameraIntrinsics& intrinsics,
    const Pose3& b_from_a, const KeypointRepeatabilityOptions& options = {});

}  // namespace icgm
