// Registration covariance from the agreement of a frame's registrations. Each frame of the
// odometry is registered to its reference keyframe and, with frame_extra_references, to nearby
// keyframes; those registrations use other matches and another reference, so where they agree
// the frame is well located, and where they part, their spread -- not the covariance each
// registration claims from its own inliers -- says how far off they are. The claimed covariance
// (the Hessian of the reprojection cost) is 10-20x too small in a crowd, which is why the motion
// prior scales it by motion_prior_covariance_scale; with that single scale, a registration the
// other registrations confirm weighs as little against a drifting constant-velocity prediction
// as one they contradict. The agreement covariance gives the confirmed one its own scale:
//
//   C = covariance_scale * (sum_k C_k^-1)^-1 + spread_weight * diag(s^2),
//   s^2 = sum_k (Log(mean^-1 Z_k))^2 / (n - 1)   (per axis; right perturbation at the mean)
//
// used only when at least min_registrations registrations lie within max_m / max_deg of their
// mean (otherwise the caller keeps its own weighting).
#pragma once

#include <optional>
#include <vector>

#include "core/common/pose.h"
#include "core/odometry/pose_window.h"

namespace icgm {

struct RegistrationAgreementOptions {
  double covariance_scale = 0.0;  // claimed covariance of agreeing registrations x this; 0: off
  double spread_weight = 1.0;     // x the per-axis sample variance of the registrations
  double max_m = 0.01;            // each registration within this of the mean ...
  double max_deg = 0.5;           // ... and this rotation
  int min_registrations = 2;
  bool on() const { return covariance_scale > 0.0; }
};

struct RegistrationAgreement {
  bool agree = false;  // every registration within max_m / max_deg of the mean
  Pose3 mean = Pose3::Identity();     // information-weighted mean of the registrations
  Mat6 covariance = Mat6::Identity();  // C above
  double spread_m = 0.0;    // largest distance of a registration from the mean
  double spread_deg = 0.0;  // largest rotation from the mean
};

// The comparison of `links` (T_odom_camera estimates of one frame with their claimed
// covariances): their mean, spread and whether they agree; nullopt when fewer than
// min_registrations usable links are given.
std::optional<RegistrationAgreement> CompareRegistrations(
    const std::vector<PoseLink>& links, const RegistrationAgreementOptions& options);

}  // namespace icgm
