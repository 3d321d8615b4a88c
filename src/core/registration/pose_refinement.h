// Least-squares refinement of an RGB-D relative pose on a fixed inlier set, and its covariance.
//
// RANSAC + Horn minimise 3-D point distances, which are dominated by the depth noise of the
// sensor (it grows with z^2 along the viewing ray, Khoshelham & Elberink 2012), while the
// keypoint positions are accurate to about a pixel. RefinePoseByReprojection therefore
// minimises the symmetric transfer error in pixels: each inlier's reference point projected
// into the current image and its current point projected into the reference image,
//     E(T) = sum_i rho(|pi(T^-1 P_ref,i) - u_cur,i|^2) + rho(|pi(T P_cur,i) - u_ref,i|^2),
// with a Huber rho, by Gauss-Newton on a right perturbation T <- T * Exp(eps).
//
// Covariance convention (both functions): 6x6 covariance of eps = (tx, ty, tz, rx, ry, rz) in
// the current camera frame, T_true = T * Exp(eps) (the order of LogSE3/ExpSE3), estimated as
// sigma^2 (J^T W J)^-1 with sigma^2 the residual variance (sum of weighted squared residuals over
// the degrees of freedom), i.e. the Gauss-Newton approximation of the Fisher information.
#pragma once

#include <vector>

#include <Eigen/Core>
#include <opencv2/core.hpp>

#include "core/common/camera.h"
#include "core/common/pose.h"
#include "core/common/status.h"

namespace icgm {

// [v]x: the cross-product matrix, [v]x w = v x w.
Eigen::Matrix3d Skew(const Eigen::Vector3d& v);

// Derivative of the pinhole projection (CameraIntrinsics::Project) at camera point x (z > 0).
Eigen::Matrix<double, 2, 3> ProjectionJacobian(const Eigen::Vector3d& x, const CameraIntrinsics& k);

struct ReprojectionRefineOptions {
  int max_iterations = 10;
  double huber_px = 2.0;
  // Stop when the update is below this (translation m + rotation rad).
  double min_step = 1e-7;
};

// Refines *pose (p_ref = pose * p_cur) over the correspondences listed in `indices`. Leaves
// *pose untouched and returns an error when the system is degenerate. `pixel_sigma_px`
// (optional, one per correspondence) is the keypoint position uncertainty, e.g. the pyramid
// scale of the detection; residuals are whitened by it.
Status RefinePoseByReprojection(const std::vector<Eigen::Vector3d>& points_ref,
                                const std::vector<cv::Point2f>& pixels_ref,
                                const std::vector<Eigen::Vector3d>& points_cur,
                                const std::vector<cv::Point2f>& pixels_cur,
                                const std::vector<int>& indices, const CameraIntrinsics& intrinsics,
                                const ReprojectionRefineOptions& options, Pose3* pose,
                                Mat6* covariance, double* rms_px,
                                const std::vector<double>* pixel_sigma_px = nullptr);

// Covariance of the point-to-point alignment p_ref = pose * p_cur over `indices`.
Mat6 PointToPointCovariance(const std::vector<Eigen::Vector3d>& points_ref,
                            const std::vector<Eigen::Vector3d>& points_cur,
                            const std::vector<int>& indices, const Pose3& pose);

}  // namespace icgm
