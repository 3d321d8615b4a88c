// Options of the SLAM system (slam_system.h) and where they come from: the front end from
// config/odometry.yaml + config/icgm.yaml, the hybrid map from config/map.yaml, and the
// loop-closure registration from a `keyframe_registration:` section of config/map.yaml
// (optional: absent means the defaults of LoopRegistrationOptions).
#pragma once

#include <string>

#include "core/common/enum_names.h"
#include "core/icgm/robust_feature_tracker.h"
#include "core/map/map_builder.h"
#include "core/odometry/frontend_types.h"
#include "core/slam/keyframe_conversion.h"
#include "core/slam/keyframe_registration.h"
#include "core/slam/map_refinement.h"
#include "core/slam/nearest_keyframe_localizer.h"

namespace icgm {

class OptionReader;

// Where keyframes made while localizing go.
enum class LocalizationKeyframes { kNone, kSession };

template <>
struct EnumNames<LocalizationKeyframes> {
  static constexpr EnumName<LocalizationKeyframes> kNames[] = {
      {LocalizationKeyframes::kNone, "none"}, {LocalizationKeyframes::kSession, "session"}};
};

// Localization mode (SlamSystem::SetMode): the learned map is the reference and never changes.
struct LocalizationOptions {
  // Keyframes made while localizing (`localization.keyframes`): none (only used to localize
  // against the map) or session (kept in a separate session of the map, saved only to the
  // localization file).
  LocalizationKeyframes keyframes = LocalizationKeyframes::kNone;
  // Once localized, each keyframe is located by registering it with the learned keyframes
  // nearest to its predicted pose (`nearest_keyframes`, `nearest_radius_m`,
  // `nearest_radius_deg`; count 0: off, the thesis's dictionary candidates only); when none
  // verifies, the dictionary relocalization runs as without it.
  NearestKeyframeOptions nearest;
  // While localized, fixes farther from the odometry's prediction are refused (`fix_gate_m`,
  // `fix_gate_m_per_m`, `fix_gate_deg`; 0 m: off, the relocalization guard only).
  FixGateOptions fix_gate;
  // Fixes fused with the odometry's prediction (`fuse_fixes` and the `fuse_*` sigmas) instead of
  // replacing it.
  OdometryFixFilterOptions fix_filter;
};

// Which ICGM flags choose a map keyframe's features (`map_features.source` of config/map.yaml):
//  - kReferenceKeyframe (ours): the front end's ICGM between the keyframe and its reference
//    keyframe (with the wheel motion prior when the odometry sets it), the matches the
//    registration used;
//  - kTracker (thesis 6.1.3.1): the robust feature tracker of config/icgm.yaml `tracker:` run
//    over consecutive frames, i.e. double-directional ICGM with S = 3 in the thesis profile
//    (C = A u B of (I_t-1, I_t) and (I_t, I_t+1)). It needs the frame after the keyframe, so
//    SlamSystem holds each keyframe back one frame (SlamSystem::ProcessFrame).
enum class MapFeatureSource { kReferenceKeyframe, kTracker };

template <>
struct EnumNames<MapFeatureSource> {
  static constexpr EnumName<MapFeatureSource> kNames[] = {
      {MapFeatureSource::kReferenceKeyframe, "reference_keyframe"},
      {MapFeatureSource::kTracker, "tracker"}};
};

struct MapFeatureOptions {
  MapFeatureSource source = MapFeatureSource::kReferenceKeyframe;
  // kTracker: mode, window and features / matcher / ICGM of the tracker, from config/icgm.yaml
  // (`tracker:`, `features:`, `matcher:`, `icgm:`; LoadSlamOptions).
  TrackerOptions tracker;
};

struct SlamOptions {
  FrontendOptions frontend;
  MapBuilderOptions map;
  LoopRegistrationOptions keyframe_registration;
  KeyframeConversionOptions conversion;
  MapFeatureOptions map_features;  // `map_features:` of config/map.yaml (+ icgm.yaml's tracker)
  // Bundle adjustment of the whole map (map_refinement.h), from `map_refinement:` and
  // `bundle_adjustment:` of config/map.yaml.
  MapRefinementOptions map_refinement;
  // false: keyframes are chained into the map without loop-closure queries (comparison runs).
  bool loop_closure = true;
  // false: the front end alone (odometry runs): no keyframe enters the map, so the map stays
  // empty and the map trajectory equals the odometry.
  bool build_map = true;
  std::string session_name = "session";  // name of the sessions this system opens
  LocalizationOptions localization;      // `localization:` of config/map.yaml (optional)
};

// Reads <config_dir>/odometry.yaml, icgm.yaml (front end and map_features.tracker) and map.yaml.
// Throws LoadError (missing file or bad value, or a key no option reads: a misspelt key is an
// error naming it).
SlamOptions LoadSlamOptions(const std::string& config_dir);

// The map part of SlamOptions (map, keyframe_registration, map_refinement, bundle_adjustment)
// from the root of a map.yaml; the front end is left as it is. Throws LoadError.
void ReadMapSlamOptions(const OptionReader& map_root, SlamOptions* options);

// The `localization:` section of a map.yaml (read by ReadMapSlamOptions; the caller rejects
// its unknown keys). Throws LoadError on a bad value.
void ReadLocalizationOptions(const OptionReader& section, LocalizationOptions* options);

// Throws LoadError when `options` ask for what this build lacks (the pose-graph back end
// without Ceres). ReadMapSlamOptions and the SlamSystem constructor call it.
void CheckBackEndAvailable(const SlamOptions& options);

// Throws LoadError when the map's dictionary cannot hold the front end's descriptors
// (`dictionary.descriptor_type` of map.yaml against `features.detector` of icgm.yaml, e.g. a
// binary dictionary with SURF), naming both keys. Without a map (build_map false) any pair is
// fine. The SlamSystem constructor calls it.
void CheckFeaturesFitDictionary(const SlamOptions& options);

}  // namespace icgm
