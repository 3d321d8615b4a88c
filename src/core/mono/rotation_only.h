// Rotation of a camera between two views from point matches alone, when it turned about its
// centre (pure rotation: the bearing in view b is R_b_a times the one in view a, whatever the
// depth). Two matches fix R (orthogonal Procrustes, Kabsch 1976 / Horn 1987 on unit bearings)
// in a RANSAC; the rotation is then refit on every inlier. What the rotation leaves
// unexplained, the angle between R_b_a * a and b, is the parallax the translation made: its
// median over the inliers tells a low-parallax view (a rotation explains the matches, the
// translation is not observable) from one whose translation can be estimated (PnP,
// triangulation). Model selection between a homography of the plane at infinity and the
// essential matrix, in the spirit of ORB-SLAM's initialization, reduced to one number.
#pragma once

#include <cstdint>
#include <vector>

#include <Eigen/Core>

#include "core/common/camera.h"
#include "core/common/status.h"

namespace icgm {

struct RotationOnlyOptions {
  // A match is an inlier of R when R_b_a * a and b are within this angle (rad of arc as pixels
  // at the focal length: inlier_px / fx).
  double inlier_px = 3.0;
  int iterations = 100;
  int min_inliers = 20;
  unsigned rng_seed = 7;  // fixed: the same matches give the same rotation
};

struct RotationOnlyResult {
  Status status = Status::Ok();
  Eigen::Matrix3d b_R_a = Eigen::Matrix3d::Identity();  // bearing in b = b_R_a * bearing in a
  std::vector<uint8_t> inliers;                         // per match
  size_t num_inliers = 0;
  // Median over the inliers of the angle between b_R_a * a and b (deg).
  double median_parallax_deg = 0.0;
};

// Unit bearing of a pixel on the ideal pinhole image of `intrinsics`.
Eigen::Vector3d PixelBearing(const CameraIntrinsics& intrinsics, const Eigen::Vector2d& px);

// `pixels_a[k]` <-> `pixels_b[k]` on the ideal pinhole images of `intrinsics`. Never throws;
// fewer than min_inliers inliers give a non-ok status (with the best rotation found).
RotationOnlyResult EstimateRotationOnly(const std::vector<Eigen::Vector2d>& pixels_a,
                                        const std::vector<Eigen::Vector2d>& pixels_b,
                                        const CameraIntrinsics& intrinsics,
                                        const RotationOnlyOptions& options = {});

// Median over the matches flagged in `use` (all when empty) of the angle (deg) between
// b_R_a * a and b: the parallax left once a known rotation is taken out. 0 without matches.
double MedianParallaxDeg(const Eigen::Matrix3d& b_R_a, const std::vector<Eigen::Vector2d>& pixels_a,
                         const std::vector<Eigen::Vector2d>& pixels_b,
                         const CameraIntrinsics& intrinsics, const std::vector<uint8_t>& use = {});

}  // namespace icgm
