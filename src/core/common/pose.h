// Core pose type and SE(3) helpers. A Pose3 maps points from its child frame into its parent
// frame: p_parent = T_parent_child * p_child. The thesis's composition L_n = L_(n-1) (+) R_n
// (eq. 6.1) is T_world_n = T_world_(n-1) * T_(n-1)_n, and L_b (-) L_a is L_a^-1 * L_b.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>

namespace icgm {

using Pose3 = Eigen::Isometry3d;
using Vec3 = Eigen::Vector3d;
using Quat = Eigen::Quaterniond;
using Mat6 = Eigen::Matrix<double, 6, 6>;
using Vec6 = Eigen::Matrix<double, 6, 1>;

inline Pose3 MakePose(const Vec3& t, const Quat& q) {
  Pose3 p = Pose3::Identity();
  p.linear() = q.normalized().toRotationMatrix();
  p.translation() = t;
  return p;
}

// a (+) b: compose.
inline Pose3 Compose(const Pose3& a, const Pose3& b) { return a * b; }
// b (-) a: the pose of b expressed in a's frame (relative motion from a to b).
inline Pose3 Between(const Pose3& a, const Pose3& b) { return a.inverse() * b; }

inline double TranslationNorm(const Pose3& p) { return p.translation().norm(); }
// Rotation angle of p in radians, in [0, pi].
double RotationAngleRad(const Pose3& p);

// Interpolates between a (s=0) and b (s=1): slerp for rotation, lerp for translation.
Pose3 Interpolate(const Pose3& a, const Pose3& b, double s);

// Re-orthonormalizes the rotation part (after repeated composition).
Pose3 Orthonormalized(const Pose3& p);

// 6-vector twist (tx, ty, tz, rx, ry, rz) with rotation as an angle-axis vector; ExpSE3 inverts
// LogSE3 for the decoupled (translation, rotation-vector) parameterization.
Eigen::Matrix<double, 6, 1> LogSE3(const Pose3& p);
Pose3 ExpSE3(const Eigen::Matrix<double, 6, 1>& v);

}  // namespace icgm
