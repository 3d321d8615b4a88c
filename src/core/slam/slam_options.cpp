#include "core/slam/slam_options.h"

#include "core/common/option_reader.h"
#include "core/map/map_options.h"

namespace icgm {

SlamOptions LoadSlamOptions(const std::string& config_dir) {
  SlamOptions options;
  const OptionReader odometry = OptionReader::FromFile(config_dir + "/odometry.yaml");
  const OptionReader icgm = OptionReader::FromFile(config_dir + "/icgm.yaml");
  ReadFrontendOptions(odometry, icgm, &options.frontend);
  ReadMapSlamOptions(OptionReader::FromFile(config_dir + "/map.yaml"), &options);
  return options;
}

void ReadMapSlamOptions(const OptionReader& map_root, SlamOptions* options) {
  ReadOptions(map_root, &options->map);
  ReadOptions(map_root.Section("keyframe_registration"), &options->keyframe_registration);
  ReadOptions(map_root.Section("map_refinement"), &options->map_refinement);
  ReadOptions(map_root.Section("bundle_adjustment"), &options->map_refinement.bundle_adjustment);
}

}  // namespace icgm
