// Relative motion of a calibrated camera between two views from point matches: the essential
// matrix by the five-point algorithm (Nister 2004) in RANSAC (OpenCV findEssentialMat), the
// motion (R, t with |t| = 1) chosen by the cheirality test (recoverPose), then every inlier
// refined by a two-view bundle adjustment on the inliers (refine) and triangulated
// (triangulation.h). The translation's length is unobservable from two images:
// the caller fixes the scale.
#pragma once

#include <cstdint>
#include <vector>

#include <Eigen/Core>

#include "core/common/camera.h"
#include "core/common/pose.h"
#include "core/common/status.h"
#include "core/mono/triangulation.h"

namespace icgm {

struct TwoViewOptions {
  double ransac_threshold_px = 1.0;
  double ransac_confidence = 0.999;
  // The matches handed to RANSAC in an order drawn from this seed (ransac_order.h; 0: input
  // order, OpenCV's fixed draws).
  uint64_t ransac_order_seed = 0;
  TriangulationCheck triangulation;
  // Two-view bundle adjustment of the motion on the RANSAC inliers before triangulating.
  bool refine = true;
  int refine_max_iterations = 20;
  // Wall-clock cap of that adjustment; 0: none (iterations decide, repeatable under load).
  double refine_max_solver_time_s = 0.0;
};

struct TwoViewResult {
  Status status = Status::Ok();
  // The second camera in the first camera's frame, T_a_b, with a unit translation.
  Pose3 a_b = Pose3::Identity();
  // Per match: 1 when it fits the essential matrix and the chosen motion.
  std::vector<uint8_t> inliers;
  size_t num_inliers = 0;
  // Per match: the triangulated point in camera a's frame (for |t| = 1), valid where
  // triangulated[k] is 1.
  std::vector<Eigen::Vector3d> points_a;
  std::vector<uint8_t> triangulated;
  size_t num_triangulated = 0;
  // Median angle between the viewing rays of the triangulated points (deg): the parallax.
  double median_parallax_deg = 0.0;
};

// `pixels_a[k]` <-> `pixels_b[k]` on the ideal pinhole images of `intrinsics`. Never throws;
// fewer than 5 matches or a degenerate configuration give a non-ok status.
TwoViewResult RecoverTwoViewMotion(const std::vector<Eigen::Vector2d>& pixels_a,
                                   const std::vector<Eigen::Vector2d>& pixels_b,
                                   const CameraIntrinsics& intrinsics,
                                   const TwoViewOptions& options = {});

}  // namespace icgm
