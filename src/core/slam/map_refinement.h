// Bundle adjustment of the whole hybrid map (beyond the thesis, after its eq. 6.4 correction or
// the pose graph): the keyframe poses L_n are refined from the keypoint observations
// themselves, not from the relative poses they were chained from.
//
//  1. Pairs (keyframes placed by wheel odometry excepted, see skip_wheel_keyframes): every keyframe
//  is registered (KeyframeRegistration: ratio test, ICGM, RANSAC +
//     Horn, refinement) with the keyframes it is linked to (odometry and loop links) and with
//     its nearest keyframes by current pose (within max_neighbour_distance_m / _angle_deg), up
//     to max_neighbours per keyframe. A registration that disagrees with the current poses by
//     more than max_disagreement_m / _deg is not used (a wrong match of a repeated structure).
//  2. Tracks: the inlier keypoint pairs are joined (union-find) into tracks, one 3-D point per
//     track; a track that would see one keyframe twice keeps its first keypoint there.
//  3. Bundle adjustment (core/optimization/bundle_adjustment.h): keyframe poses and points from
//     pixels and depths, the odometry links as relative-pose priors (information scaled by
//     odometry_prior_weight) so keyframes without shared points stay attached, keyframe 0 held.
// The result is a pose per keyframe; the caller decides whether to apply it.
#pragma once

#include <vector>

#include "core/common/camera.h"
#include "core/common/pose.h"
#include "core/common/status.h"
#include "core/map/hybrid_map.h"
#include "core/optimization/bundle_adjustment.h"
#include "core/slam/keyframe_registration.h"

namespace icgm {

class OptionReader;

struct MapRefinementOptions {
  // Offline runs refine the map once at the end (also with --refine), the map-building
  // nodelet on its save service.
  bool enabled = false;
  int max_neighbours = 8;
  double max_neighbour_distance_m = 1.0;
  double max_neighbour_angle_deg = 45.0;
  double max_disagreement_m = 0.3;
  double max_disagreement_deg = 15.0;
  double odometry_prior_weight = 0.1;
  // Keyframes whose R_n came from wheel odometry (registration failed or was overruled by the
  // vision/wheel gate: a walker filling the view) take part through their priors only.
  bool skip_wheel_keyframes = true;
  BundleAdjustmentOptions bundle_adjustment;
};

// Reads a `map_refinement:` section (all fields but bundle_adjustment); throws LoadError.
void ReadOptions(const OptionReader& reader, MapRefinementOptions* options);

struct MapRefinementSummary {
  int pairs_tried = 0;
  int pairs_used = 0;
  int tracks = 0;
  BaSummary bundle_adjustment;
  double time_s = 0.0;
};

// Refined keyframe poses, indexed by keyframe id, in *poses (unchanged map poses on error).
Status RefineMapPoses(const HybridMap& map, const KeyframeRegistration& registration,
                      const CameraIntrinsics& intrinsics, const MapRefinementOptions& options,
                      std::vector<Pose3>* poses, MapRefinementSummary* summary = nullptr);

}  // namespace icgm
