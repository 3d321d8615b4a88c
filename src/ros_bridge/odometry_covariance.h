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
//
// The twist (nav_msgs/Odometry twist: velocities of child_frame_id, the base, in its own frame,
// (vx vy vz wx wy wz)) of one step of duration dt is the constant body velocity that makes the
// step, xi = Log(T_base_prev_cur) / dt (the SE(3) logarithm of se3_geodesic.h). Its covariance
// follows from the step's: the camera-frame right perturbation moves into the base frame with
// the adjoint of X = base_to_camera (T_base = X T_cam X^-1, so T_cam Exp(eps) gives
// T_base Exp(Ad_X eps), Ad_X = [[R, [t]x R], [0, R]]), and through the logarithm with
// J = d Log(T_base Exp(d)) / d d at d = 0 (the inverse right Jacobian of SE(3), close to I for
// small steps):  Sigma_xi = J Ad_X Sigma_eps Ad_X^T J^T / dt^2.
#pragma once

#include <array>
#include <string>

#include <geometry_msgs/TwistWithCovariance.h>
#include <nav_msgs/Odometry.h>
#include <ros/time.h>

#include "core/common/pose.h"
#include "core/odometry/odometry_fusion.h"

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

// Twist of the base over one step and its covariance (see above).
struct StepTwist {
  Vec6 twist = Vec6::Zero();       // (vx vy vz wx wy wz): m/s, rad/s, in the base frame
  Mat6 covariance = Mat6::Zero();  // of `twist`, same order
};
// `camera_prev_cur`: the camera's step (p_prev = camera_prev_cur * p_cur), `step_covariance` its
// covariance in the registration convention, `dt_s` > 0 its duration.
StepTwist BaseStepTwist(const Pose3& camera_prev_cur, const Mat6& step_covariance,
                        const Pose3& base_to_camera, double dt_s);

// nav_msgs/Odometry's twist field: linear, angular and the row-major covariance.
geometry_msgs::TwistWithCovariance ToTwistWithCovarianceMsg(const StepTwist& twist);

// A 6x6 matrix as a message's row-major covariance array.
std::array<double, 36> RowMajor(const Mat6& m);

// An isotropic step covariance: sigma_m^2 on the translation, sigma_rad^2 on the rotation.
Mat6 IsotropicStepCovariance(double sigma_m, double sigma_rad);

// Steps not measured by vision: sigma = floor + per_m * the step's length (or angle), for a
// wheel step; ten times that for a constant-velocity (or no) step.
struct FallbackStepSigmas {
  double floor_m = 0.002;
  double floor_rad = 0.002;
  double per_m = 0.05;
};
// The covariance of one fused step (registration convention): the registration's own for a
// visual step, the fallback model otherwise.
Mat6 FusedStepCovariance(const FusionStep& step, const Mat6& registration_covariance,
                         const FallbackStepSigmas& fallback);

// The fused odometry message: pose of the base (child_frame) in odom with its covariance
// (OdometryCovariance::BaseMsg) and the last step's twist.
nav_msgs::Odometry ToFusedOdometryMsg(const ros::Time& stamp, const std::string& odom_frame,
                                      const std::string& child_frame, const Pose3& odom_base,
                                      const std::array<double, 36>& pose_covariance,
                                      const StepTwist& twist);

}  // namespace icgm::ros_bridge
