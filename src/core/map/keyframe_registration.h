// 6D registration between two stored metric models for loop closure (thesis 6.1.1.2): the
// models keep ICGM features and their camera-frame 3D points, not depth images, so the
// registration works on those points:
//  1. descriptor matches query -> candidate (DescriptorMatcher, ratio test);
//  2. optionally ICGM (Algorithm 1) on the matched pixel positions, dropping geometrically
//     inconsistent matches (moving people, repeated texture);
//  3. RANSAC + Horn on the 3D pairs with finite depth (ransac_horn.h), giving
//     beta = the query camera in the candidate camera frame (p_candidate = beta * p_query);
//  4. plausibility: |t(beta)| <= max_translation_m, angle <= max_rotation_rad.
// The information matrix is an isotropic approximation from the inlier residuals:
// sigma_t = rmse / sqrt(inliers) (floored at min_sigma_m), sigma_r = sigma_t / spread with
// spread the RMS distance of the inlier points from their centroid.
// This is the RegisterFn the map builder uses; RegisterRgbd fits when depth images are at hand.
#pragma once

#include <string>
#include <vector>

#include "core/features/descriptor_matcher.h"
#include "core/icgm/icgm_matcher.h"
#include "core/map/loop_closure.h"
#include "core/registration/ransac_horn.h"

namespace icgm {

class OptionReader;

struct KeyframeRegistrationOptions {
  MatcherOptions matcher;
  bool use_icgm = true;
  IcgmOptions icgm;
  RansacOptions ransac;
  double max_translation_m = 2.0;
  double max_rotation_rad = 1.0;
  double min_sigma_m = 0.005;
};

// Reads `matcher:`/`icgm:` from `icgm_root` (config/icgm.yaml) and `loop_closure.registration:`
// (use_icgm, inlier_threshold_m, max_iterations, min_inliers, max_translation_m,
// max_rotation_rad) from `map_root` (config/map.yaml). Throws LoadError on bad values.
// `unused_keys` (optional) receives unknown keys of the registration section.
void ReadOptions(const OptionReader& icgm_root, const OptionReader& map_root,
                 KeyframeRegistrationOptions* options,
                 std::vector<std::string>* unused_keys = nullptr);

RegistrationOutcome RegisterKeyframes(const Keyframe& query, const Keyframe& candidate,
                                      const KeyframeRegistrationOptions& options);

// Binds the options into a RegisterFn for MapBuilder::AddKeyframe.
RegisterFn MakeKeyframeRegisterFn(const KeyframeRegistrationOptions& options);

}  // namespace icgm
