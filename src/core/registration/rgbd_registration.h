// 6-D rigid transformation between two RGB-D metric models (thesis ch. 6.1.1.1, "6D rigid
// transformation [40] between 3D points clouds ... we try to get an inliers' set by RANSAC [41];
// if we can not get a good inliers' set, we treat this calculation as failed").
//
// Pipeline of RegisterRgbd for matched keypoints pts_ref[i] <-> pts_cur[i] (e.g. the ICGM-kept
// matches between frame x - phi and frame x):
//  1. lift both keypoints with their registered depth (depth_points.h); a match is dropped, the
//     reason counted, when either side has no usable depth;
//  2. RANSAC + Horn on the 3-D pairs (ransac_horn.h), refined on all inliers;
//  3. optionally, Gauss-Newton on the symmetric reprojection error of the inliers
//     (pose_refinement.h), which weights the accurate pixel positions over the noisy depth;
//  4. plausibility: translation and rotation within bounds.
// The result carries the inlier set, inlier ratio, 3-D rmse and a covariance (pose_refinement.h
// convention: 6x6 over (t, r) of a right perturbation in the current camera frame).
// A rejected estimate keeps the best pose found (if any) and says why in `status`:
// "too few 3D matches: 7 < 12", "too few inliers: 8 < 10", "implausible motion: 0.9 m > 0.5 m".
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include <opencv2/core.hpp>

#include "core/common/camera.h"
#include "core/common/pose.h"
#include "core/common/status.h"
#include "core/registration/depth_points.h"

namespace icgm {

class OptionReader;

struct RegistrationOptions {
  int min_matches_3d = 12;
  int min_inliers = 10;
  // Accept only when inliers / 3-D matches reaches this (0 disables).
  double min_inlier_ratio = 0.0;
  double inlier_threshold_m = 0.03;
  // > 0: RANSAC judges inliers in the images (ransac_horn.h ReprojectionInlierTest: symmetric
  // reprojection within this many pixels times the keypoint sigma, depths within
  // inlier_threshold_m + reprojection_depth_rel_per_m * z^2) instead of by 3-D distance.
  double ransac_reprojection_px = 0.0;
  double reprojection_depth_rel_per_m = 0.015;
  int max_iterations = 300;
  double ransac_confidence = 0.995;
  int refine_rounds = 3;
  // LO-RANSAC (ransac_horn.h RansacOptions::local_optimization): each new best sample refitted
  // on its inliers before it competes.
  bool ransac_local_optimization = false;
  double max_translation_m = 0.5;
  double max_rotation_deg = 30.0;
  uint64_t rng_seed = 7;
  // Keypoint depth validity (missing, range, discontinuity).
  DepthPointOptions depth;
  // Final Gauss-Newton on the symmetric reprojection error of the inliers.
  bool refine_reprojection = true;
  int reprojection_iterations = 10;
  double reprojection_huber_px = 2.0;
};

// Fills `options` from a `registration:` section; throws LoadError on bad values.
void ReadOptions(const OptionReader& reader, RegistrationOptions* options);

struct RegistrationResult {
  Status status = Status::Ok();
  // Current camera in the reference camera frame: p_ref = relative_pose * p_cur.
  Pose3 relative_pose = Pose3::Identity();
  Mat6 covariance = Mat6::Identity();
  size_t matches_2d = 0;
  size_t matches_3d = 0;
  size_t inliers = 0;
  double inlier_ratio = 0.0;         // inliers / matches_3d
  double rmse_m = 0.0;               // 3-D residual over the inliers
  double reprojection_rms_px = 0.0;  // after refinement (0 when not refined)
  // Indices into pts_ref / pts_cur of the inlier matches, increasing.
  std::vector<int> inlier_indices;
  DepthRejectCounts depth_rejects;
};

// `depth_*_m`: CV_32FC1 metres registered to the colour image; pts_ref.size() must equal
// pts_cur.size() (a mismatch is reported in `status`). `pixel_sigma_px` (optional, one per
// match, > 0) is the keypoint position uncertainty used to weight the reprojection refinement,
// e.g. scale_factor^octave for pyramid detectors. Never throws.
RegistrationResult RegisterRgbd(const std::vector<cv::Point2f>& pts_ref, const cv::Mat& depth_ref_m,
                                const std::vector<cv::Point2f>& pts_cur, const cv::Mat& depth_cur_m,
                                const CameraIntrinsics& intrinsics,
                                const RegistrationOptions& options,
                                const std::vector<double>* pixel_sigma_px = nullptr);

}  // namespace icgm
