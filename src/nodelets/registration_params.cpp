#include "nodelets/registration_params.h"

#include <algorithm>
#include <string>

#include "core/common/option_reader.h"
#include "core/slam/map_feature_tracking.h"
#include "nodelets/nodelet_params.h"

namespace icgm::nodelets {

RegistrationParams ReadRegistrationParams(const ros::NodeHandle& pnh) {
  RegistrationParams p;
  p.live.wheel_lead_s = Param(pnh, "wheel_lead_s", p.live.wheel_lead_s);
  p.live.pacing.max_wait_s = Param(pnh, "max_wait_for_wheel_s", p.live.pacing.max_wait_s);
  p.live.pacing.max_pending =
      static_cast<size_t>(std::max(1, Param(pnh, "max_pending_frames", 100)));
  p.keyframe_hold_max_s = Param(pnh, "keyframe_hold_max_s", p.keyframe_hold_max_s);
  p.queue_size = Param(pnh, "queue_size", p.queue_size);
  p.approx_sync = Param(pnh, "approx_sync", p.approx_sync);
  const std::string config_file = Param(pnh, "config_file", "");
  const std::string icgm_file = Param(pnh, "icgm_config_file", "");
  const std::string map_config_file = Param(pnh, "map_config_file", "");
  if (!config_file.empty()) {
    const auto odometry = OptionReader::FromFile(config_file);
    ReadFrontendOptions(odometry, icgm_file.empty() ? odometry : OptionReader::FromFile(icgm_file),
                        &p.frontend);
  }
  if (!map_config_file.empty()) {
    p.map_features =
        LoadMapFeatureOptions(map_config_file, icgm_file.empty() ? config_file : icgm_file);
  }
  return p;
}

}  // namespace icgm::nodelets
