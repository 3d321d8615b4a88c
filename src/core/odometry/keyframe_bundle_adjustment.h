// Windowed bundle adjustment of the RGB-D front end's last keyframes
// (rgbd_frontend.h, frontend.keyframe_ba_keyframes).
//
// A single registration against far, plain walls hardly tells a pan from a sideways slide: for
// points at depth z the two differ by the parallax between near and far points only, which
// among walkers is often below the noise. Several keyframes seeing the same static points from
// different places constrain it jointly. When a new keyframe is made, the verified-static
// keypoints (outside dynamic regions, lifted with their depth) of the last few keyframes and
// the new one are associated across every pair of them (projection with the current pose
// estimates within match_px, descriptor distance, depth agreement; each keypoint joins one
// track), and poses and points are optimised together over the pixel and the depth residual of
// every observation with a Huber loss (core/optimization/bundle_adjustment.h), the oldest
// keyframes held fixed as the gauge. The corrected poses replace the keyframes' poses, so
// later frames are registered to the corrected references.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include <Eigen/Core>
#include <opencv2/core.hpp>

#include "core/common/camera.h"
#include "core/common/pose.h"
#include "core/common/status.h"

namespace icgm {

struct KeyframeBaOptions {
  // Keyframes in the window, the new one included (the most recent ones); < 3: off.
  int keyframes = 0;
  // The oldest this many keyframes of the window are held fixed (the gauge, >= 1).
  int fixed_keyframes = 1;
  // The window's keyframes are picked going back in time, each at least this far (translation
  // or rotation) from the one picked after it, so that their baseline shows parallax; 0: the
  // most recent ones (the front end's choice; AdjustKeyframes takes the views it is given).
  double min_spacing_m = 0.0;
  double min_spacing_deg = 0.0;
  // Association: a keypoint of one keyframe projected into another with the current poses
  // must land within this many pixels (x the keypoint's pixel sigma) of its partner...
  double match_px = 6.0;
  // ... whose descriptor lies at most this far (Hamming for binary descriptors, else L2) ...
  double max_descriptor_distance = 50.0;
  // ... and whose depth agrees within depth_abs_m + depth_rel_per_m * z^2 (set by the front end
  // from registration.inlier_threshold_m and reprojection_depth_rel_per_m).
  double depth_abs_m = 0.03;
  double depth_rel_per_m = 0.015;
  // Fewer points seen by two keyframes: the poses are left unchanged.
  int min_points = 30;
  int iterations = 10;
  double huber_sigmas = 2.0;  // Huber threshold of the whitened residual
  // Depth noise sigma(z) = depth_sigma_m + depth_sigma_per_m2 * z^2 of the depth residual.
  double depth_sigma_m = 0.002;
  double depth_sigma_per_m2 = 0.003;
  // A solution that moves any keyframe further than this is rejected (the poses stay).
  double max_correction_m = 0.05;
  double max_correction_deg = 2.0;
  // > 0: each keyframe's registration to an earlier keyframe of the window joins as a
  // relative-pose term with its registration covariance times this (it claims 10-20x too
  // little among walkers); 0: the points alone.
  double link_covariance_scale = 0.0;
};

// One keyframe as the adjustment sees it.
struct KeyframeBaView {
  Pose3 odom_camera = Pose3::Identity();  // current estimate of T_odom_camera
  std::vector<cv::Point2f> pixels_px;
  std::vector<double> pixel_sigma_px;          // one per keypoint, > 0
  std::vector<Eigen::Vector3d> points_camera;  // per keypoint; non-finite: no depth
  cv::Mat descriptors;                         // one row per keypoint
  bool binary = true;
  std::vector<uint8_t> usable;  // per keypoint: 1 = verified static (empty: all)
  // The registration that placed this keyframe, when it was registered to an earlier view of
  // the list: that view's index, T_that_this as registered, its covariance (pose_refinement.h
  // convention: right perturbation, (t, r)).
  int link_from = -1;
  Pose3 link_relative = Pose3::Identity();
  Mat6 link_covariance = Mat6::Identity();
};

struct KeyframeBaResult {
  Status status = Status::Ok();
  // Per view: the adjusted T_odom_camera (the input poses when not ok).
  std::vector<Pose3> odom_camera;
  size_t points = 0;        // tracks seen by two keyframes or more
  size_t observations = 0;  // their observations in the last solve
  size_t outliers = 0;
  double initial_rms = 0.0;  // whitened residual rms before / after
  double final_rms = 0.0;
  double max_correction_m = 0.0;  // largest pose change among the views
  double max_correction_deg = 0.0;
};

// Tracks across `views`: per view and keypoint the track id, -1 when the keypoint is in no
// track seen by two views. Exposed for tests.
std::vector<std::vector<int>> AssociateKeyframes(const std::vector<KeyframeBaView>& views,
                                                 const CameraIntrinsics& intrinsics,
                                                 const KeyframeBaOptions& options,
                                                 size_t* num_tracks);

// Adjusts the views' poses (the first fixed_keyframes held); never throws.
KeyframeBaResult AdjustKeyframes(const std::vector<KeyframeBaView>& views,
                                 const CameraIntrinsics& intrinsics,
                                 const KeyframeBaOptions& options);

}  // namespace icgm
