// A pose on the floor plan (x, y, yaw about z) and its conversions to and from Pose3. Navigation
// works in the plane of base_link (x forward, y left, z up, on the floor).
#pragma once

#include <cmath>

#include <Eigen/Core>

#include "core/common/pose.h"

namespace icgm {

struct Pose2D {
  double x_m = 0.0;
  double y_m = 0.0;
  double yaw_rad = 0.0;

  Eigen::Vector2d position() const { return {x_m, y_m}; }
  // A point given in this pose's frame, in the parent frame.
  Eigen::Vector2d ToParent(const Eigen::Vector2d& p) const {
    const double c = std::cos(yaw_rad), s = std::sin(yaw_rad);
    return {x_m + c * p.x() - s * p.y(), y_m + s * p.x() + c * p.y()};
  }
  // A point given in the parent frame, in this pose's frame.
  Eigen::Vector2d ToLocal(const Eigen::Vector2d& p) const {
    const double c = std::cos(yaw_rad), s = std::sin(yaw_rad);
    const double dx = p.x() - x_m, dy = p.y() - y_m;
    return {c * dx + s * dy, -s * dx + c * dy};
  }
};

// Projection of a 3-D pose onto the floor plan: translation's x, y and the heading of its x axis.
inline Pose2D ToPose2D(const Pose3& pose) {
  const Eigen::Vector3d x_axis = pose.linear().col(0);
  return {pose.translation().x(), pose.translation().y(), std::atan2(x_axis.y(), x_axis.x())};
}

inline Pose3 ToPose3(const Pose2D& pose) {
  return MakePose(Vec3(pose.x_m, pose.y_m, 0.0),
                  Quat(Eigen::AngleAxisd(pose.yaw_rad, Vec3::UnitZ())));
}

// Angle wrapped to (-pi, pi].
inline double WrapAngleRad(double a) {
  a = std::fmod(a + M_PI, 2.0 * M_PI);
  if (a < 0) a += 2.0 * M_PI;
  return a - M_PI;
}

}  // namespace icgm
