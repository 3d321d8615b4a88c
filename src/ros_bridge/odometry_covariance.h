// Pose covariance of the fused odometry in nav_msgs/Odometry's convention.
//
// The front end's registration covariance (pose_refinement.h) is that of a right perturbation
// eps = (tx, ty, tz, rx, ry, rz) of a relative pose in the current camera frame,
// T_true = T * Exp(eps). nav_msgs/Odometry's pose covariance is row-major 6x6 over
// (x, y, z, rotation about the fixed x, y, z axes) of the pose in header.frame_id (odom): the
// position error and a rotation error applied on the left, p_true = p + dp,
// R_true = Exp(dtheta) R. Chaining steps to first order,
//     dp_k = dp_(k-1) + dtheta_(k-1) x (p_k - p_(k-1)) + R_k eps_t,
//     dtheta_k = dtheta_(k-1) + R_k eps_r,
// i.e. Sigma_k = F Sigma_(k-1) F^T + G Sigma_eps G^T with F = [[I, -[p_k - p_(k-1)]x], [0, I]]
// and G = diag(R_k, R_k); the base pose T_odom_base = T_odom_camera * base_to_camera^-1 shares
// the rotation error, and its position error gains dtheta x (p_base - p_camera).
#pragma once

#include <array>

#include "core/common/pose.h"

namespace icgm::ros_bridge {

class OdometryCovariance {
 public:
  // One step of the camera to `odom_camera_after` from `odom_camera_before`, with the step's
  // covariance in the registration convention.
  void AddStep(const Pose3& odom_camera_before, const Pose3& odom_camera_after,
               const Mat6& step_covariance);
  // Covariance of the camera pose, (x y z rx ry rz) in the odometry frame.
  const Mat6& camera() const { return camera_; }
  // Covariance of T_odom_base in the message's order, row-major.
  std::array<double, 36> BaseMsg(const Pose3& odom_camera, const Pose3& base_to_camera) const;

 private:
  Mat6 camera_ = Mat6::Zero();
};

// An isotropic step covariance: sigma_m^2 on the translation, sigma_rad^2 on the rotation.
Mat6 IsotropicStepCovariance(double sigma_m, double sigma_rad);

}  // namespace icgm::ros_bridge
