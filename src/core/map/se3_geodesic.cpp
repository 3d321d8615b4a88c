#include "core/map/se3_geodesic.h"

#include <cmath>

namespace icgm {
namespace {

Eigen::Matrix3d Hat(const Vec3& w) {
  Eigen::Matrix3d m;
  m << 0, -w.z(), w.y(), w.z(), 0, -w.x(), -w.y(), w.x(), 0;
  return m;
}

// V(w) = I + (1 - cos t)/t^2 W + (t - sin t)/t^3 W^2, series near t = 0.
Eigen::Matrix3d LeftJacobian(const Vec3& w) {
  const double t = w.norm();
  const Eigen::Matrix3d W = Hat(w);
  double b;
  double c;
  if (t < 1e-5) {
    b = 0.5 - t * t / 24.0;
    c = 1.0 / 6.0 - t * t / 120.0;
  } else {
    b = (1.0 - std::cos(t)) / (t * t);
    c = (t - std::sin(t)) / (t * t * t);
  }
  return Eigen::Matrix3d::Identity() + b * W + c * W * W;
}

}  // namespace

Vec6 GeodesicLog(const Pose3& pose) {
  const Eigen::AngleAxisd aa(pose.linear());
  const Vec3 w = aa.axis() * aa.angle();
  Vec6 out;
  out.head<3>() = LeftJacobian(w).partialPivLu().solve(pose.translation());
  out.tail<3>() = w;
  return out;
}

Pose3 GeodesicExp(const Vec6& twist) {
  const Vec3 w = twist.tail<3>();
  const double angle = w.norm();
  Pose3 p = Pose3::Identity();
  if (angle > 1e-15) p.linear() = Eigen::AngleAxisd(angle, w / angle).toRotationMatrix();
  p.translation() = LeftJacobian(w) * twist.head<3>();
  return p;
}

}  // namespace icgm
