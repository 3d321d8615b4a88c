#include "ros_bridge/odometry_covariance.h"

#include <algorithm>

#include "core/map/se3_geodesic.h"
#include "ros_bridge/conversions.h"

namespace icgm::ros_bridge {
namespace {

Eigen::Matrix3d Skew(const Eigen::Vector3d& v) {
  Eigen::Matrix3d s;
  s << 0, -v.z(), v.y(), v.z(), 0, -v.x(), -v.y(), v.x(), 0;
  return s;
}

Mat6 PositionShift(const Eigen::Vector3d& d) {
  Mat6 f = Mat6::Identity();
  f.block<3, 3>(0, 3) = -Skew(d);
  return f;
}

// Adjoint of `x` on (translation, rotation) twists: Exp(Ad_x eps) = x Exp(eps) x^-1.
Mat6 Adjoint(const Pose3& x) {
  Mat6 ad = Mat6::Zero();
  ad.block<3, 3>(0, 0) = x.linear();
  ad.block<3, 3>(0, 3) = Skew(x.translation()) * x.linear();
  ad.block<3, 3>(3, 3) = x.linear();
  return ad;
}

// d GeodesicLog(t * Exp(d)) / d d at d = 0, by central differences (the logarithm is smooth
// there for rotations below pi; the step h keeps truncation and rounding errors near 1e-10).
Mat6 LogJacobian(const Pose3& t) {
  constexpr double h = 1e-6;
  Mat6 j;
  for (int i = 0; i < 6; ++i) {
    Vec6 d = Vec6::Zero();
    d(i) = h;
    j.col(i) = (GeodesicLog(t * ExpSE3(d)) - GeodesicLog(t * ExpSE3(-d))) / (2 * h);
  }
  return j;
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
  return RowMajor(f * camera_ * f.transpose());
}

StepTwist BaseStepTwist(const Pose3& camera_prev_cur, const Mat6& step_covariance,
                        const Pose3& base_to_camera, double dt_s) {
  const Pose3 base_prev_cur = base_to_camera * camera_prev_cur * base_to_camera.inverse();
  const Mat6 to_twist = LogJacobian(base_prev_cur) * Adjoint(base_to_camera) / dt_s;
  StepTwist out;
  out.twist = GeodesicLog(base_prev_cur) / dt_s;
  out.covariance = to_twist * step_covariance * to_twist.transpose();
  out.covariance = 0.5 * (out.covariance + out.covariance.transpose());
  return out;
}

geometry_msgs::TwistWithCovariance ToTwistWithCovarianceMsg(const StepTwist& twist) {
  geometry_msgs::TwistWithCovariance msg;
  msg.twist.linear.x = twist.twist(0);
  msg.twist.linear.y = twist.twist(1);
  msg.twist.linear.z = twist.twist(2);
  msg.twist.angular.x = twist.twist(3);
  msg.twist.angular.y = twist.twist(4);
  msg.twist.angular.z = twist.twist(5);
  const std::array<double, 36> c = RowMajor(twist.covariance);
  std::copy(c.begin(), c.end(), msg.covariance.begin());
  return msg;
}

std::array<double, 36> RowMajor(const Mat6& m) {
  std::array<double, 36> out{};
  for (int i = 0; i < 6; ++i)
    for (int j = 0; j < 6; ++j) out[6 * i + j] = m(i, j);
  return out;
}

Mat6 IsotropicStepCovariance(double sigma_m, double sigma_rad) {
  Mat6 c = Mat6::Zero();
  c.diagonal() << Eigen::Vector3d::Constant(sigma_m * sigma_m),
      Eigen::Vector3d::Constant(sigma_rad * sigma_rad);
  return c;
}

Mat6 FusedStepCovariance(const FusionStep& step, const Mat6& registration_covariance,
                         const FallbackStepSigmas& fallback) {
  if (step.source == MotionSource::kVision) return registration_covariance;
  const double length_m = step.camera_prev_cur.translation().norm();
  const double angle_rad = Eigen::AngleAxisd(step.camera_prev_cur.linear()).angle();
  const double scale = step.source == MotionSource::kWheel ? 1.0 : 10.0;
  return IsotropicStepCovariance(scale * (fallback.floor_m + fallback.per_m * length_m),
                                 scale * (fallback.floor_rad + fallback.per_m * angle_rad));
}

nav_msgs::Odometry ToFusedOdometryMsg(const ros::Time& stamp, const std::string& odom_frame,
                                      const std::string& child_frame, const Pose3& odom_base,
                                      const std::array<double, 36>& pose_covariance,
                                      const StepTwist& twist) {
  nav_msgs::Odometry odom;
  odom.header.stamp = stamp;
  odom.header.frame_id = odom_frame;
  odom.child_frame_id = child_frame;
  odom.pose.pose = ToPoseMsg(odom_base);
  std::copy(pose_covariance.begin(), pose_covariance.end(), odom.pose.covariance.begin());
  odom.twist = ToTwistWithCovarianceMsg(twist);
  return odom;
}

}  // namespace icgm::ros_bridge
