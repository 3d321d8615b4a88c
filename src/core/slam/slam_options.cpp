#include "core/slam/slam_options.h"

#include <vector>

#include "core/common/option_reader.h"
#include "core/map/map_options.h"

namespace icgm {

SlamOptions LoadSlamOptions(const std::string& config_dir) {
  SlamOptions options;
  const OptionReader odometry = OptionReader::FromFile(config_dir + "/odometry.yaml");
  const OptionReader icgm = OptionReader::FromFile(config_dir + "/icgm.yaml");
  ReadFrontendOptions(odometry, icgm, &options.frontend);
  const OptionReader map = OptionReader::FromFile(config_dir + "/map.yaml");
  std::vector<std::string> unused;
  ReadOptions(map, &options.map, &unused);
  const OptionReader registration = map.Section("keyframe_registration");
  ReadOptions(registration, &options.keyframe_registration);
  for (const auto& key : registration.UnusedKeys()) unused.push_back(key);
  if (!unused.empty()) {
    throw LoadError(config_dir + "/map.yaml: unknown key '" + unused.front() + "'");
  }
  return options;
}

}  // namespace icgm
