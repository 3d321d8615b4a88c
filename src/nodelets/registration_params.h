// Private parameters of the rgbd_registration nodelet: the front end's options (~config_file =
// odometry.yaml, ~icgm_config_file = icgm.yaml), the map features its keyframes carry
// (~map_config_file = map.yaml's map_features), and the pacing of frames by the wheels.
#pragma once

#include <ros/node_handle.h>

#include "core/odometry/rgbd_frontend.h"
#include "core/slam/live_frontend.h"
#include "core/slam/slam_options.h"

namespace icgm::nodelets {

struct RegistrationParams {
  FrontendOptions frontend;        // code defaults without ~config_file
  MapFeatureOptions map_features;  // code defaults without ~map_config_file
  // ~max_wait_for_wheel_s, ~max_pending_frames (pacing), ~wheel_lead_s: wheel samples up to
  // this after a frame's stamp
  LiveFrontendOptions live;
  double keyframe_hold_max_s = 0.5;  // wall time without frames before a held keyframe leaves
  int queue_size = 10;               // features + depth synchroniser
  bool approx_sync = true;
};

// Reads the parameters; throws LoadError for a bad configuration file.
RegistrationParams ReadRegistrationParams(const ros::NodeHandle& pnh);

}  // namespace icgm::nodelets
