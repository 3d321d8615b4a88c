#include "ros_bridge/odometry_covariance.h"

namespace icgm::ros_bridge {
namespace {

Mat6 PositionShift(const Eigen::Vector3d& d) {
  Mat6 f = Mat6::Identity();
  f.block<3, 3>(0, 3) << 0, d.z(), -d.y(), -d.z(), 0, d.x(), d.y(), -d.x(), 0;  // -[d]x
  return f;
}

}  // namespace

void OdometryCovariance::AddStep(const Pose3& odom_camera_before, const Pose3& odom_camera_after,
                                 const Mat6& step_covariance) {
  const Mat6 f = PositionShift(odom_camera_after.translation() - odom_camera_before.translation());
  Mat6 g = Mat6::Zero();
  g.block<3, 3>(0, 0) = odom_camera_after.linear();
  g.block<3, 3>(3, 3) = odom_camera_after.linear();
  camera_ = f * camera_ * f.transpose() + g * step_covariance * g.transpose();
  camera_ = 0.5 * (camera_ + camera_.transpose());
}

std::array<double, 36> OdometryCovariance::BaseMsg(const Pose3& odom_camera,
                                                   const Pose3& base_to_camera) const {
  const Pose3 odom_base = odom_camera * base_to_camera.inverse();
  const Mat6 f = PositionShift(odom_base.translation() - odom_camera.translation());
  const Mat6 base = f * camera_ * f.transpose();
  std::array<double, 36> out{};
  for (int i = 0; i < 6; ++i)
    for (int j = 0; j < 6; ++j) out[6 * i + j] = base(i, j);
  return out;
}

Mat6 IsotropicStepCovariance(double sigma_m, double sigma_rad) {
  Mat6 c = Mat6::Zero();
  c.diagonal() << Eigen::Vector3d::Constant(sigma_m * sigma_m),
      Eigen::Vector3d::Constant(sigma_rad * sigma_rad);
  return c;
}

}  // namespace icgm::ros_bridge
