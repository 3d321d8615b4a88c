// Local map tracking of the RGB-D front end (rgbd_frontend.h, frontend.local_map_keyframes).
//
// The verified-static 3-D points of the last few keyframes (the features a keyframe keeps
// outside its dynamic regions, lifted with its depth) are fused into one point set in the odom
// frame. A frame's pose estimate is then refined against that set: every map point is projected
// with the estimate, matched to the nearest current keypoint by descriptor within a search
// radius (each current keypoint keeps its best map point), and the pose minimises the Huber
// reprojection error of all matches (Gauss-Newton, right perturbation T <- T * Exp(eps), the
// convention of pose_refinement.h), re-matching with a shrinking radius. A single reference
// keyframe sees the room only where walkers left it visible at that instant; the points of
// several keyframes cover more of it, and points on walkers that moved since no longer project
// onto their features.
#pragma once

#include <cstddef>
#include <vector>

#include <Eigen/Core>
#include <opencv2/core.hpp>

#include "core/common/camera.h"
#include "core/common/pose.h"
#include "core/common/status.h"

namespace icgm {

struct LocalMapOptions {
  // Keyframes whose points form the map (the most recent ones, and the frame's reference);
  // 0: off.
  int keyframes = 0;
  // Matching radius around a map point's projection at the first round (px); later rounds
  // halve it down to 2 * huber_px.
  double search_px = 10.0;
  // Largest descriptor distance of a match (Hamming for binary descriptors, else L2).
  double max_descriptor_distance = 50.0;
  // Fewer matches: the estimate is left unchanged.
  int min_matches = 30;
  int rounds = 3;
  int iterations = 8;     // Gauss-Newton iterations per round
  double huber_px = 2.0;  // in units of each keypoint's pixel sigma
  // A refinement that moves the estimate further than this is rejected (the start stays).
  double max_correction_m = 0.05;
  double max_correction_deg = 2.0;
  // true: the refined pose is averaged with the registered one, each weighted by its
  // covariance (the reprojection error alone hardly tells a pan from a sideways slide; the
  // registration's 3-D points do); false: the refined pose replaces it.
  bool fuse = false;
  // ... with the local map's covariance multiplied by this (> 1: the registration weighs more).
  double covariance_scale = 1.0;
  // true (with a constant-velocity prediction): the refined pose is kept only where it lies no
  // further from the prediction's position than the registered pose does, plus
  // toward_prediction_slack_m. Keyframes made while a walker filling the view carried the
  // registration hold the walker's points as static; refined against them, the pose follows
  // the walker further away from the hand's inertia.
  bool toward_prediction = false;
  double toward_prediction_slack_m = 0.0;
  // With a current depth image: a match counts only where the depth there agrees with the map
  // point's within depth_abs_m + depth_rel_per_m * z^2 (set from registration's
  // inlier_threshold_m and reprojection_depth_rel_per_m).
  double depth_abs_m = 0.03;
  double depth_rel_per_m = 0.015;
};

// Map points in the odom frame with their descriptors (one row each).
struct LocalMapPoints {
  std::vector<Eigen::Vector3d> odom_points;
  cv::Mat descriptors;
  bool binary = true;
  size_t size() const { return odom_points.size(); }
};

// Adds the keypoints of one keyframe whose `use` flag is set and whose point is finite:
// `points_camera` (camera frame, metres) moved to the odom frame by `odom_camera`, with their
// descriptor rows.
void AddKeyframePoints(const cv::Mat& descriptors, bool binary,
                       const std::vector<Eigen::Vector3d>& points_camera,
                       const std::vector<uint8_t>& use, const Pose3& odom_camera,
                       LocalMapPoints* map);

struct LocalMapTrackResult {
  Status status = Status::Ok();
  Pose3 odom_camera = Pose3::Identity();  // refined T_odom_camera (the start when not ok)
  size_t matches = 0;                     // map points matched in the last round
  double rms_px = 0.0;                    // whitened reprojection rms of the last round
  // Covariance of the refined pose (right perturbation in the camera frame, the convention of
  // pose_refinement.h): residual variance times (J^T W J)^-1.
  Mat6 covariance = Mat6::Identity();
};

// Refines `start` (T_odom_camera of the current frame) against `map`. `keypoints` and
// `descriptors` are the current frame's, `pixel_sigma_px` one per keypoint (> 0), `usable`
// (empty: all) flags the keypoints that may be matched (outside dynamic regions). `depth_m`
// (CV_32FC1 metres, or empty) is the current frame's depth for the depth agreement check.
LocalMapTrackResult TrackLocalMap(const LocalMapPoints& map,
                                  const std::vector<cv::KeyPoint>& keypoints,
                                  const cv::Mat& descriptors,
                                  const std::vector<double>& pixel_sigma_px,
                                  const std::vector<uint8_t>& usable, const cv::Mat& depth_m,
                                  const Pose3& start, const CameraIntrinsics& intrinsics,
                                  const LocalMapOptions& options);

}  // namespace icgm
