#include "core/slam/slam_options.h"

#include "core/common/option_reader.h"
#include "core/map/map_options.h"

namespace icgm {

SlamOptions LoadSlamOptions(const std::string& config_dir) {
  SlamOptions options;
  const OptionReader odometry = OptionReader::FromFile(config_dir + "/odometry.yaml");
  const OptionReader icgm = OptionReader::FromFile(config_dir + "/icgm.yaml");
  ReadFrontendOptions(odometry, icgm, &options.frontend);
  const OptionReader map = OptionReader::FromFile(config_dir + "/map.yaml");
  ReadOptions(map, &options.map);
  ReadOptions(map.Section("keyframe_registration"), &options.keyframe_registration);
  return options;
}

}  // namespace icgm
