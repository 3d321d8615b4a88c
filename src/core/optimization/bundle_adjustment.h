// Bundle adjustment of RGB-D keyframes: camera poses and 3-D points refined together from
// every keypoint observation (pixel position and registered depth), with optional
// relative-pose priors between cameras (e.g. odometry links of the map, which also hold
// cameras that see no shared point in place).
//
//   min  sum_obs rho(|r_obs|^2) + sum_priors |r_prior|^2
//   r_obs   = [(pi(T_wc^-1 X) - u) / sigma_px;  (z_c - d) / sigma_d(d)]      (ceres_costs.h)
//   r_prior = sqrt(information) * [t(E); 2 vec(q(E))]
// sigma_px is the keypoint localisation sigma (pyramid scale), sigma_d the depth noise of a
// structured-light sensor, sigma_d(z) = depth_sigma_m + depth_sigma_per_m2 * z^2 (it grows
// with z^2, Khoshelham & Elberink 2012), rho a Huber loss on the whitened residual.
// Pairwise registration uses each depth once per pair; here every point gets one position
// consistent with all its views, which averages the depth noise of the keyframes seeing it.
//
// After the first solve, observations whose whitened squared error exceeds outlier_chi2 are
// dropped and the problem is solved again (outlier_rounds times).
// Builds without Ceres: BundleAdjust then returns "built without Ceres" and changes nothing.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "core/common/camera.h"
#include "core/common/pose.h"
#include "core/common/status.h"

namespace icgm {

class OptionReader;

struct BundleAdjustmentOptions {
  int max_iterations = 30;
  // Wall-clock cap of each solve; 0: none (max_iterations alone decides, so the result does
  // not depend on how loaded the machine is).
  double max_solver_time_s = 10.0;
  // Huber threshold on the whitened observation residual (in sigmas); <= 0: plain squares.
  double huber_sigma = 2.0;
  bool use_depth = true;
  double depth_sigma_m = 0.002;
  double depth_sigma_per_m2 = 0.003;
  // Whitened squared error above which an observation is an outlier (3 dof, 99%: 11.34).
  double outlier_chi2 = 11.34;
  int outlier_rounds = 1;
  // Points seen by fewer cameras (after outlier removal) are left out.
  int min_observations = 2;
};

// Fills `options` from a `bundle_adjustment:` section; throws LoadError on bad values.
void ReadOptions(const OptionReader& reader, BundleAdjustmentOptions* options);

struct BaObservation {
  int camera = -1;
  int point = -1;
  Eigen::Vector2d pixel_px = Eigen::Vector2d::Zero();
  double pixel_sigma_px = 1.0;
  double depth_m = 0.0;  // <= 0 or NaN: no depth measurement
};

struct BaRelativePose {
  int from = -1;
  int to = -1;
  Pose3 measured = Pose3::Identity();   // to in from's frame
  Mat6 information = Mat6::Identity();  // (t, r) twist layout
};

struct BaProblem {
  std::vector<Pose3> world_camera;  // T_world_camera per camera
  std::vector<uint8_t> fixed;       // per camera: 1 = held constant (gauge)
  std::vector<Eigen::Vector3d> points_world;
  std::vector<BaObservation> observations;
  std::vector<BaRelativePose> priors;
};

struct BaSummary {
  int cameras = 0;        // cameras in the problem
  int fixed_cameras = 0;  // of which held constant
  int points = 0;
  int observations = 0;
  int outliers = 0;
  double initial_rms = 0.0;  // whitened observation residual, per residual
  double final_rms = 0.0;
  int iterations = 0;
  double time_s = 0.0;
  std::string report;
};

// Optimises problem->world_camera and problem->points_world in place. `inlier` (optional) gets
// one flag per observation (0: dropped as outlier or unused). Never throws; bad indices or a
// failed solve leave the problem unchanged and return an error.
Status BundleAdjust(const CameraIntrinsics& intrinsics, const BundleAdjustmentOptions& options,
                    BaProblem* problem, BaSummary* summary = nullptr,
                    std::vector<uint8_t>* inlier = nullptr);

}  // namespace icgm
