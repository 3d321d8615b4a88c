// The map builder's services on the running map (core LiveMap): `~save_map` (icgm_slam/SaveMap),
// `~load_map` (icgm_slam/LoadMap, merge or replace) and `~set_mode` (icgm_slam/SetMapMode). Each
// answers with success and the core's message; a save or load is followed by `done`, e.g. the
// map products' policy, and a mode switch is preceded by it (kBeforeModeSwitch: the keyframes
// made before the switch enter the map first).
#pragma once

#include <functional>

#include <ros/ros.h>

#include <icgm_slam/LoadMap.h>
#include <icgm_slam/SaveMap.h>
#include <icgm_slam/SetMapMode.h>

#include "core/slam/live_map.h"

namespace icgm::nodelets {

class MapServices {
 public:
  enum class Done { kSaved, kLoaded, kBeforeModeSwitch };
  // `map` outlives this object; `done` runs on the service's callback queue.
  MapServices(ros::NodeHandle& pnh, LiveMap* map, std::function<void(Done)> done);

 private:
  bool Save(icgm_slam::SaveMap::Request& req, icgm_slam::SaveMap::Response& res);
  bool Load(icgm_slam::LoadMap::Request& req, icgm_slam::LoadMap::Response& res);
  bool Mode(icgm_slam::SetMapMode::Request& req, icgm_slam::SetMapMode::Response& res);

  LiveMap* map_;
  std::function<void(Done)> done_;
  ros::ServiceServer save_, load_, mode_;
};

}  // namespace icgm::nodelets
