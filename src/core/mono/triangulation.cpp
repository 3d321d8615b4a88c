#include "core/mono/triangulation.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

#include <Eigen/Dense>

namespace icgm {

namespace {
// Rows of the DLT system contributed by one view: x (P row 3) - (P row 1), y (P row 3) - P row 2.
void AddView(const CameraIntrinsics& k, const Pose3& world_camera, const Eigen::Vector2d& px,
             Eigen::Matrix4d* a, int row) {
  const Pose3 camera_world = world_camera.inverse();
  Eigen::Matrix<double, 3, 4> p;
  p.leftCols<3>() = camera_world.rotation();
  p.col(3) = camera_world.translation();
  // Normalized image coordinates: the intrinsics drop out of the system.
  const double x = (px.x() - k.cx_px) / k.fx_px;
  const double y = (px.y() - k.cy_px) / k.fy_px;
  a->row(row) = x * p.row(2) - p.row(0);
  a->row(row + 1) = y * p.row(2) - p.row(1);
}

// Angle (deg) between two rays.
double RayAngleDeg(const Eigen::Vector3d& ray_a, const Eigen::Vector3d& ray_b) {
  const double cos_angle = ray_a.dot(ray_b) / (ray_a.norm() * ray_b.norm());
  return std::acos(std::max(-1.0, std::min(1.0, cos_angle))) * 180.0 / M_PI;
}
}  // namespace

double ReprojectionErrorPx(const CameraIntrinsics& intrinsics, const Pose3& world_camera,
                           const Eigen::Vector3d& point_world, const Eigen::Vector2d& pixel) {
  const Eigen::Vector3d c = world_camera.inverse() * point_world;
  if (!(c.z() > 1e-9)) return std::numeric_limits<double>::infinity();
  return (intrinsics.Project(c) - pixel).norm();
}

TriangulatedPoint TriangulatePoint(const CameraIntrinsics& intrinsics, const Pose3& world_camera_a,
                                   const Eigen::Vector2d& pixel_a, const Pose3& world_camera_b,
                                   const Eigen::Vector2d& pixel_b,
                                   const TriangulationCheck& check) {
  TriangulatedPoint out;
  Eigen::Matrix4d a;
  AddView(intrinsics, world_camera_a, pixel_a, &a, 0);
  AddView(intrinsics, world_camera_b, pixel_b, &a, 2);
  const Eigen::JacobiSVD<Eigen::Matrix4d> svd(a, Eigen::ComputeFullV);
  const Eigen::Vector4d h = svd.matrixV().col(3);
  if (std::abs(h.w()) < 1e-12 || !h.allFinite()) {
    out.status = Status::Error("point at infinity");
    return out;
  }
  out.point_world = h.head<3>() / h.w();
  const Eigen::Vector3d ray_a = out.point_world - world_camera_a.translation();
  const Eigen::Vector3d ray_b = out.point_world - world_camera_b.translation();
  out.angle_deg = RayAngleDeg(ray_a, ray_b);
  const double err_a = ReprojectionErrorPx(intrinsics, world_camera_a, out.point_world, pixel_a);
  const double err_b = ReprojectionErrorPx(intrinsics, world_camera_b, out.point_world, pixel_b);
  if (!std::isfinite(err_a) || !std::isfinite(err_b)) {
    out.status = Status::Error("point behind a camera");
  } else if (std::max(err_a, err_b) > check.max_reprojection_px) {
    out.status = Status::Error("reprojection error " + std::to_string(std::max(err_a, err_b)) +
                               " px > " + std::to_string(check.max_reprojection_px));
  } else if (out.angle_deg < check.min_angle_deg) {
    out.status = Status::Error("triangulation angle " + std::to_string(out.angle_deg) + " deg < " +
                               std::to_string(check.min_angle_deg));
  } else if (check.max_depth_baselines > 0.0) {
    const double baseline = (world_camera_a.translation() - world_camera_b.translation()).norm();
    const double depth = std::max(ray_a.norm(), ray_b.norm());
    if (depth > check.max_depth_baselines * baseline) {
      out.status =
          Status::Error("depth above " + std::to_string(check.max_depth_baselines) + " baselines");
    }
  }
  return out;
}

double ExpectedParallaxDeg(const CameraIntrinsics& intrinsics, const Pose3& world_camera_a,
                           const Pose3& world_camera_b, const Eigen::Vector2d& pixel_b,
                           double depth_b) {
  const Eigen::Vector3d point =
      world_camera_b * intrinsics.BackProject(pixel_b.x(), pixel_b.y(), depth_b);
  return RayAngleDeg(point - world_camera_a.translation(), point - world_camera_b.translation());
}

}  // namespace icgm
