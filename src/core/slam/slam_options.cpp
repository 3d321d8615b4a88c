#include "core/slam/slam_options.h"

#include "core/common/option_reader.h"
#include "core/features/feature_extractor.h"
#include "core/map/map_options.h"
#include "core/map/pose_graph_optimizer.h"

namespace icgm {

SlamOptions LoadSlamOptions(const std::string& config_dir) {
  SlamOptions options;
  const OptionReader odometry = OptionReader::FromFile(config_dir + "/odometry.yaml");
  const OptionReader icgm = OptionReader::FromFile(config_dir + "/icgm.yaml");
  ReadFrontendOptions(odometry, icgm, &options.frontend);
  ReadOptions(icgm, &options.map_features.tracker);
  ReadMapSlamOptions(OptionReader::FromFile(config_dir + "/map.yaml"), &options);
  return options;
}

void ReadMapSlamOptions(const OptionReader& map_root, SlamOptions* options) {
  ReadOptions(map_root, &options->map);
  const OptionReader registration = map_root.Section("keyframe_registration");
  const OptionReader refinement = map_root.Section("map_refinement");
  const OptionReader bundle_adjustment = map_root.Section("bundle_adjustment");
  ReadOptions(registration, &options->keyframe_registration);
  ReadOptions(refinement, &options->map_refinement);
  ReadOptions(bundle_adjustment, &options->map_refinement.bundle_adjustment);
  const OptionReader localization = map_root.Section("localization");
  ReadLocalizationOptions(localization, &options->localization);
  const OptionReader map_features = map_root.Section("map_features");
  map_features.ReadEnum("source", &options->map_features.source);
  OptionReader::RejectUnknownKeys(
      {&registration, &refinement, &bundle_adjustment, &localization, &map_features, &map_root});
  CheckBackEndAvailable(*options);
}

void ReadLocalizationOptions(const OptionReader& section, LocalizationOptions* options) {
  LocalizationOptions& loc = *options;
  section.ReadEnum("keyframes", &loc.keyframes);
  section.Read("nearest_keyframes", &loc.nearest.count, 0, 20);
  section.Read("nearest_radius_m", &loc.nearest.radius_m, 0.01, 10.0);
  section.Read("nearest_radius_deg", &loc.nearest.radius_deg, 1.0, 180.0);
  section.Read("fix_gate_m", &loc.fix_gate.max_m, 0.0, 10.0);
  section.Read("fix_gate_m_per_m", &loc.fix_gate.m_per_m, 0.0, 1.0);
  section.Read("fix_gate_deg", &loc.fix_gate.max_deg, 0.1, 180.0);
  section.Read("fuse_fixes", &loc.fix_filter.enabled);
  section.Read("fuse_sigma_m_per_m", &loc.fix_filter.sigma_m_per_m, 0.0, 1.0);
  section.Read("fuse_sigma_rad_per_m", &loc.fix_filter.sigma_rad_per_m, 0.0, 1.0);
  section.Read("fuse_floor_sigma_m", &loc.fix_filter.floor_sigma_m, 0.0, 1.0);
  section.Read("fuse_floor_sigma_rad", &loc.fix_filter.floor_sigma_rad, 0.0, 1.0);
  section.Read("fuse_measurement_floor_sigma_m", &loc.fix_filter.measurement_floor_sigma_m, 0.0,
               1.0);
  section.Read("fuse_measurement_floor_sigma_rad", &loc.fix_filter.measurement_floor_sigma_rad, 0.0,
               1.0);
}

void CheckBackEndAvailable(const SlamOptions& options) {
  if (options.map.loop_closure.correction == LoopCorrection::kPoseGraph &&
      !PoseGraphOptimizer::Available()) {
    throw LoadError(
        "loop_closure.correction: pose_graph needs Ceres, which this build lacks "
        "(use semi_consensus, or install libceres-dev and rebuild)");
  }
}

void CheckFeaturesFitDictionary(const SlamOptions& options) {
  if (!options.build_map) return;
  const Detector detector = options.frontend.features.detector;
  // SIFT and SURF describe with floats, the others (ORB, AKAZE, GFTT+ORB) with bits.
  const bool binary_features = detector != Detector::kSift && detector != Detector::kSurf;
  const bool binary = options.map.dictionary.descriptor_type == DescriptorType::kBinary;
  if (binary != binary_features) {
    throw LoadError(std::string("dictionary.descriptor_type '") +
                    NameOf(options.map.dictionary.descriptor_type) +
                    "' (map.yaml) cannot hold the descriptors of features.detector '" +
                    NameOf(detector) + "' (icgm.yaml): use " +
                    (binary_features ? "binary" : "float"));
  }
}

}  // namespace icgm
