#include "core/common/pose.h"

#include <algorithm>
#include <cmath>

namespace icgm {

double RotationAngleRad(const Pose3& p) {
  const double c = std::clamp((p.linear().trace() - 1.0) * 0.5, -1.0, 1.0);
  return std::acos(c);
}

Pose3 Interpolate(const Pose3& a, const Pose3& b, double s) {
  const Quat qa(a.linear());
  const Quat qb(b.linear());
  return MakePose((1.0 - s) * a.translation() + s * b.translation(), qa.slerp(s, qb));
}

Pose3 Orthonormalized(const Pose3& p) {
  return MakePose(p.translation(), Quat(p.linear()).normalized());
}

Eigen::Matrix<double, 6, 1> LogSE3(const Pose3& p) {
  Eigen::Matrix<double, 6, 1> v;
  const Eigen::AngleAxisd aa(p.linear());
  v.head<3>() = p.translation();
  v.tail<3>() = aa.axis() * aa.angle();
  return v;
}

Pose3 ExpSE3(const Eigen::Matrix<double, 6, 1>& v) {
  Pose3 p = Pose3::Identity();
  const Vec3 w = v.tail<3>();
  const double angle = w.norm();
  if (angle > 1e-15) p.linear() = Eigen::AngleAxisd(angle, w / angle).toRotationMatrix();
  p.translation() = v.head<3>();
  return p;
}

}  // namespace icgm
