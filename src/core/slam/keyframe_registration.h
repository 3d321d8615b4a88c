// 6-D registration between two metric models of the hybrid map, the RegisterFn of loop-closure
// detection (thesis 6.1.1.2: "6D rigid transformation between current model and 3 best scored
// models ... by comparing the output RANSAC modeling results ... we choose the best relative
// pose beta_i"). For the query (current model) and a candidate (earlier model):
//  1. putative matches of their descriptors (DescriptorMatcher, ratio test);
//  2. ICGM (thesis Algorithm 1, eq. 4.19) on the matched keypoint pixel positions, candidate
//     image as I_0, query image as I_1: only the consistent set goes on (use_icgm);
//  3. RANSAC + Horn (ransac_horn.h) on the models' stored 3-D points (3D-3D, no images needed);
//  4. optionally Gauss-Newton on the symmetric reprojection error of the inliers
//     (pose_refinement.h), which needs the intrinsics the keypoints were measured with;
//  5. acceptance: at least min_inliers inliers and an inlier ratio of min_inlier_ratio.
// Result: beta = the query camera in the candidate's camera frame (p_cand = beta * p_query),
// the inlier count and the information (inverse covariance, (t, r) of a right perturbation of
// beta, i.e. the twist layout of se3_geodesic.h to first order) for eq. 6.2.
// A rejected registration keeps the reason in `status` ("too few ICGM matches: 8 < 20").
#pragma once

#include <string>

#include "core/common/camera.h"
#include "core/features/descriptor_matcher.h"
#include "core/icgm/icgm_matcher.h"
#include "core/map/keyframe.h"
#include "core/map/loop_closure.h"
#include "core/registration/pose_refinement.h"
#include "core/registration/ransac_horn.h"

namespace icgm {

class OptionReader;

struct LoopRegistrationOptions {
  MatcherOptions matcher;  // ratio test; the other matcher fields keep their defaults
  bool use_icgm = true;
  IcgmOptions icgm;                // threshold (Thr of eq. 4.20), seed_pairs
  int min_matches = 20;            // putative (and ICGM-kept) matches with 3-D points needed
  RansacOptions ransac;            // inlier_threshold_m, max_iterations, confidence, min_inliers
  double min_inlier_ratio = 0.25;  // inliers / 3-D matches
  bool refine_reprojection = true;
  ReprojectionRefineOptions refine;
  // Keypoint position uncertainty of pyramid level o is octave_scale_factor^o pixels (the ORB
  // scale factor); reprojection residuals are whitened by it. <= 1 treats all levels alike.
  double octave_scale_factor = 1.2;
  // Information floor: these sigmas squared are added to the covariance diagonal (a few
  // perfect inliers must not outweigh every other hypothesis of eq. 6.2). The registration's
  // own covariance claims ~2 mm, but loop registrations are 1-1.5 cm off on fr1/xyz and 3-6 cm
  // on the simulated loops (icgm_map_eval --links), so the floor is near the real error.
  double min_sigma_m = 0.01;
  double min_sigma_rad = 0.005;
};

// Reads a `keyframe_registration:` section (keys: ratio, use_icgm, icgm_threshold,
// icgm_seed_pairs, min_matches, inlier_threshold_m, max_iterations, ransac_confidence,
// min_inliers, min_inlier_ratio, refine_reprojection, reprojection_iterations,
// reprojection_huber_px, octave_scale_factor, min_sigma_m, min_sigma_rad). Throws LoadError.
void ReadOptions(const OptionReader& reader, LoopRegistrationOptions* options);

class KeyframeRegistration {
 public:
  KeyframeRegistration(const LoopRegistrationOptions& options, const CameraIntrinsics& intrinsics);

  // Never throws. `query` and `candidate` need keypoints, descriptors and points_m.
  RegistrationOutcome Register(const Keyframe& query, const Keyframe& candidate) const;

  // A RegisterFn bound to this object (which must outlive it).
  RegisterFn AsRegisterFn() const;

  const LoopRegistrationOptions& options() const { return options_; }

 private:
  LoopRegistrationOptions options_;
  CameraIntrinsics intrinsics_;
  DescriptorMatcher matcher_;
};

}  // namespace icgm
