// Localization against the learned map's nearest keyframes (thesis 6.1.2, alpha = 1, with the
// predicted pose choosing the references instead of the dictionary): a localization keyframe is
// registered with the `count` learned keyframes nearest to its predicted pose, each verified
// registration gives a hypothesis L_k (+) beta_k, hypotheses farther from the prediction than the
// relocalization guard allows are rejected, and the rest are averaged with their registration
// information (eq. 6.2's weighted mean on SE(3)). The references are there where the
// dictionary proposes none (in the simulated crowd it proposes none at most localization
// keyframes: the walkers hide the scene), several average out the error of one registration,
// and the nearest keep the map's drift between two places out of the fix.
//
// Optionally the fix is fused with the odometry's prediction instead of replacing it
// (OdometryFixFilter): the prediction's covariance grows with the path since the last fix, the
// measurement's is the registrations' (floored), and the result is their information-weighted
// mean; a jump of alpha = 1 becomes a Kalman update.
#pragma once

#include "core/common/pose.h"
#include "core/map/hybrid_map.h"
#include "core/map/loop_closure.h"

namespace icgm {

struct NearestKeyframeOptions {
  int count = 0;             // learned keyframes registered per localization keyframe
  double radius_m = 1.0;     // ... among those within this distance of the prediction
  double radius_deg = 30.0;  // ... and this viewing-direction difference
};

// While localized, a fix must lie this close to the odometry's prediction (a tighter bound than
// the relocalization guard's 3 sigma of loop_closure.sigma_*, made for a global search):
// max_m + m_per_m * path since the last fix, and max_deg. max_m 0: off.
struct FixGateOptions {
  double max_m = 0.0;
  double m_per_m = 0.05;
  double max_deg = 10.0;
};
// Ok, or an error saying how far the fix jumps.
Status CheckFixGate(const Pose3& predicted, const Pose3& located, double path_since_fix_m,
                    const FixGateOptions& gate);

// Registers `query` (global_pose = the predicted map pose) with the nearest learned keyframes
// (id < max_id) and averages the verified, guarded hypotheses into
// result.loop_closure_pose. `verification` gives min_inliers, the link limits and the guard
// (sigma_* and gate_sigma, scaled by path_since_fix_m), `gate` a tighter one (when on). An error
// status with a reason when no keyframe lies near, none verifies or the guard rejects all.
LoopClosureResult LocateAtNearestKeyframes(const Keyframe& query, const HybridMap& map, int max_id,
                                           const RegisterFn& register_fn,
                                           const NearestKeyframeOptions& options,
                                           const LoopClosureOptions& verification,
                                           const FixGateOptions& gate, double path_since_fix_m);

struct OdometryFixFilterOptions {
  bool enabled = false;         // false: every fix replaces the pose (alpha = 1)
  double sigma_m_per_m = 0.02;  // odometry drift since the last fix, per metre driven
  double sigma_rad_per_m = 0.01;
  double floor_sigma_m = 0.002;  // added to the prediction's sigma at every fix
  double floor_sigma_rad = 0.001;
  double measurement_floor_sigma_m = 0.0;  // added to the registrations' own sigma
  double measurement_floor_sigma_rad = 0.0;
};

// The map <- odometry correction's uncertainty between fixes (6x6 covariance in the twist layout
// of se3_geodesic.h, in the camera frame at the fix).
class OdometryFixFilter {
 public:
  explicit OdometryFixFilter(const OdometryFixFilterOptions& options) : options_(options) {}
  // A fix given by hand or a global relocalization: the pose is taken as measured.
  void Reset(const Mat6& covariance);
  bool initialized() const { return initialized_; }
  // Fuses the predicted camera pose (odometry since the last fix, `path_m` long) with the
  // measured one of `measurement_information`; returns the fused pose.
  Pose3 Update(const Pose3& predicted, const Pose3& measured, const Mat6& measurement_information,
               double path_m);
  const Mat6& covariance() const { return covariance_; }

 private:
  OdometryFixFilterOptions options_;
  bool initialized_ = false;
  Mat6 covariance_ = Mat6::Identity();
};

}  // namespace icgm
