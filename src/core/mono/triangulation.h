// Triangulation of one point seen by two calibrated pinhole cameras: the linear (DLT) solution
// (Hartley & Zisserman, Multiple View Geometry, 2nd ed., sec. 12.2), accepted only when it lies
// in front of both cameras, reprojects within a pixel bound in both and the two viewing rays
// meet at a large enough angle (a small angle gives a depth dominated by pixel noise).
#pragma once

#include <Eigen/Core>

#include "core/common/camera.h"
#include "core/common/pose.h"
#include "core/common/status.h"

namespace icgm {

struct TriangulationCheck {
  double max_reprojection_px = 2.0;
  double min_angle_deg = 0.5;
  // Depth in either camera above this multiple of the baseline: rejected (0 disables).
  double max_depth_baselines = 200.0;
};

struct TriangulatedPoint {
  Status status = Status::Ok();  // why the point was rejected
  Eigen::Vector3d point_world = Eigen::Vector3d::Zero();
  double angle_deg = 0.0;  // angle between the viewing rays
};

// `world_camera_a/b`: T_world_camera of the two views; `pixel_a/b`: the observations on the
// ideal (undistorted) pinhole image of `intrinsics`.
TriangulatedPoint TriangulatePoint(const CameraIntrinsics& intrinsics, const Pose3& world_camera_a,
                                   const Eigen::Vector2d& pixel_a, const Pose3& world_camera_b,
                                   const Eigen::Vector2d& pixel_b,
                                   const TriangulationCheck& check = {});

// Angle (deg) between the rays from the centres of `world_camera_a` and `world_camera_b` to the
// point seen at `pixel_b` by camera b at depth `depth_b` (its z): the parallax such a point would
// give, independent of where camera a actually sees it.
double ExpectedParallaxDeg(const CameraIntrinsics& intrinsics, const Pose3& world_camera_a,
                           const Pose3& world_camera_b, const Eigen::Vector2d& pixel_b,
                           double depth_b);

// Reprojection error (px) of a world point in a camera; +infinity behind the camera.
double ReprojectionErrorPx(const CameraIntrinsics& intrinsics, const Pose3& world_camera,
                           const Eigen::Vector3d& point_world, const Eigen::Vector2d& pixel);

}  // namespace icgm
