// Ceres cost functors shared by the pose-graph back end (core/map/pose_graph_optimizer) and the
// bundle adjustment (bundle_adjustment.h). Poses are parameterised as world_T_camera with a
// translation block (3) and an Eigen quaternion block (x, y, z, w; EigenQuaternionManifold).
// Include only where Ceres is available (ICGM_HAVE_CERES).
#pragma once

#include <ceres/ceres.h>
#include <Eigen/Core>
#include <Eigen/Geometry>

#include "core/common/camera.h"
#include "core/common/pose.h"

namespace icgm {

// A relative-pose measurement between two poses: residual
//     sqrt_information * [t(E); 2 vec(q(E))],  E = measured^-1 * (L_from^-1 * L_to).
class RelativePoseError {
 public:
  RelativePoseError(const Pose3& measured, const Mat6& sqrt_information)
      : t_measured_(measured.translation()),
        q_measured_(Quat(measured.linear()).normalized()),
        sqrt_information_(sqrt_information) {}

  template <typename T>
  bool operator()(const T* t_from, const T* q_from, const T* t_to, const T* q_to,
                  T* residual) const {
    using Vec3T = Eigen::Matrix<T, 3, 1>;
    using QuatT = Eigen::Quaternion<T>;
    const Eigen::Map<const Vec3T> pa(t_from), pb(t_to);
    const Eigen::Map<const QuatT> qa(q_from), qb(q_to);
    const QuatT qa_inv = qa.conjugate();
    const QuatT q_ab = qa_inv * qb;
    const Vec3T t_ab = qa_inv * (pb - pa);
    const QuatT qm_inv = q_measured_.conjugate().template cast<T>();
    const QuatT q_err = qm_inv * q_ab;
    const Vec3T t_err = qm_inv * (t_ab - t_measured_.template cast<T>());
    Eigen::Matrix<T, 6, 1> e;
    e.template head<3>() = t_err;
    // q and -q are the same rotation: take the one with w >= 0 so the error is near zero.
    const T sign = q_err.w() < T(0) ? T(-1) : T(1);
    e.template tail<3>() = T(2) * sign * q_err.vec();
    Eigen::Map<Eigen::Matrix<T, 6, 1>> r(residual);
    r = sqrt_information_.template cast<T>() * e;
    return true;
  }

  static ceres::CostFunction* Create(const Pose3& measured, const Mat6& sqrt_information) {
    return new ceres::AutoDiffCostFunction<RelativePoseError, 6, 3, 4, 3, 4>(
        new RelativePoseError(measured, sqrt_information));
  }

 private:
  Vec3 t_measured_;
  Quat q_measured_;
  Mat6 sqrt_information_;
};

// One RGB-D observation of a world point X by a camera: the pixel (whitened by its sigma) and,
// when depth_sigma_m > 0, the measured depth along the optical axis (whitened by depth_sigma_m).
// p_c = q^-1 (X - t);  r = [(pi(p_c) - u) / sigma_px; (z_c - depth) / depth_sigma].
class RgbdObservationError {
 public:
  RgbdObservationError(const CameraIntrinsics& k, const Eigen::Vector2d& pixel, double sigma_px,
                       double depth_m, double depth_sigma_m)
      : fx_(k.fx_px),
        fy_(k.fy_px),
        cx_(k.cx_px),
        cy_(k.cy_px),
        pixel_(pixel),
        inv_sigma_px_(1.0 / sigma_px),
        depth_m_(depth_m),
        inv_depth_sigma_(depth_sigma_m > 0 ? 1.0 / depth_sigma_m : 0.0) {}

  template <typename T>
  bool operator()(const T* t, const T* q, const T* x, T* residual) const {
    using Vec3T = Eigen::Matrix<T, 3, 1>;
    const Eigen::Map<const Vec3T> tw(t), xw(x);
    const Eigen::Map<const Eigen::Quaternion<T>> qw(q);
    const Vec3T pc = qw.conjugate() * (xw - tw);
    if (pc.z() < T(1e-3)) return false;  // behind the camera: reject the step
    residual[0] = (T(fx_) * pc.x() / pc.z() + T(cx_) - T(pixel_.x())) * T(inv_sigma_px_);
    residual[1] = (T(fy_) * pc.y() / pc.z() + T(cy_) - T(pixel_.y())) * T(inv_sigma_px_);
    residual[2] = (pc.z() - T(depth_m_)) * T(inv_depth_sigma_);
    return true;
  }

  static ceres::CostFunction* Create(const CameraIntrinsics& k, const Eigen::Vector2d& pixel,
                                     double sigma_px, double depth_m, double depth_sigma_m) {
    return new ceres::AutoDiffCostFunction<RgbdObservationError, 3, 3, 4, 3>(
        new RgbdObservationError(k, pixel, sigma_px, depth_m, depth_sigma_m));
  }

 private:
  friend class PixelObservationCost;
  double fx_, fy_, cx_, cy_;
  Eigen::Vector2d pixel_;
  double inv_sigma_px_;
  double depth_m_;
  double inv_depth_sigma_;  // 0: no depth measurement (the third residual is always zero)
};

}  // namespace icgm
