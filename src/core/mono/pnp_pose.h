// Camera pose from 3-D map points and their pixels (perspective-n-point): EPnP (Lepetit et al.
// 2009) inside RANSAC (OpenCV solvePnPRansac), or the predicted pose when it explains more
// correspondences, then Levenberg-Marquardt refinement on the inliers.
#pragma once

#include <cstdint>
#include <optional>
#include <vector>

#include <Eigen/Core>

#include "core/common/camera.h"
#include "core/common/pose.h"
#include "core/common/status.h"

namespace icgm {

struct PnpOptions {
  double reprojection_px = 3.0;  // RANSAC inlier bound
  int iterations = 100;
  double confidence = 0.99;
  int min_inliers = 25;
  // The correspondences handed to RANSAC in an order drawn from this seed (ransac_order.h; 0:
  // input order, OpenCV's fixed draws).
  uint64_t ransac_order_seed = 0;
  // false: with a seed pose, no RANSAC: the seed's inliers are refined (pose already known).
  bool ransac = true;
};

struct PnpResult {
  Status status = Status::Ok();
  Pose3 world_camera = Pose3::Identity();
  std::vector<uint8_t> inliers;  // per correspondence
  size_t num_inliers = 0;
};

// `points_world[k]` seen at `pixels[k]` on the ideal pinhole image. `predicted_world_camera`
// (optional) seeds the solver. Never throws; fewer than min_inliers inliers is an error.
PnpResult EstimatePnpPose(const std::vector<Eigen::Vector3d>& points_world,
                          const std::vector<Eigen::Vector2d>& pixels,
                          const CameraIntrinsics& intrinsics, const PnpOptions& options,
                          const std::optional<Pose3>& predicted_world_camera = std::nullopt);

}  // namespace icgm
