// Publishes a learned map's people-free products for rviz (core/map_export/map_products.h):
// the occupancy grid (nav_msgs/OccupancyGrid) on `map/occupancy_grid` and the voxel-filtered
// static cloud (PointCloud2, x y z rgb) on `map/static_cloud`, both latched.
//
// Building them takes seconds of one core on a large map (about 11 s for 138 keyframes with
// depth images), so they are built on a worker thread from a copy of the map, and only when
// they are wanted:
//   - when a map is loaded (OnLoad): always;
//   - on request: the service `~build_map_products` (std_srvs/Trigger);
//   - when the map is saved (OnSave, e.g. every autosave): only while someone subscribes to
//     either topic; otherwise the published products are marked stale and rebuilt when the
//     first subscriber connects.
// A request made while one is being built replaces any waiting one (the latest map wins).
#pragma once

#include <condition_variable>
#include <functional>
#include <memory>
#include <mutex>
#include <string>
#include <thread>

#include <ros/ros.h>
#include <std_srvs/Trigger.h>

#include "core/map/hybrid_map.h"
#include "core/map/map_export_options.h"

namespace icgm::nodelets {

class MapProductsPublisher {
 public:
  // `map`: the current map and its stamp, or nullptr while there is none; called on the
  // callback queue of `nh` (the caller's), never on the worker.
  using MapSource = std::function<const HybridMap*(ros::Time* stamp)>;
  MapProductsPublisher(ros::NodeHandle& nh, ros::NodeHandle& pnh, const std::string& map_frame,
                       const MapExportOptions& options, MapSource map);
  ~MapProductsPublisher();

  void OnLoad() { Build("load"); }
  void OnSave();

 private:
  bool Wanted() const;
  // Copies the current map for the worker; false when there is no map.
  bool Build(const char* why);
  void Connected();
  bool RequestCb(std_srvs::Trigger::Request&, std_srvs::Trigger::Response& res);
  void Work();

  ros::Publisher grid_pub_, cloud_pub_;
  ros::ServiceServer request_srv_;
  std::string map_frame_;
  MapExportOptions options_;
  MapSource map_;
  bool stale_ = false;  // the map was saved since the last products, nobody listened
  std::mutex mutex_;
  std::condition_variable wake_;
  std::unique_ptr<HybridMap> pending_;
  ros::Time pending_stamp_;
  bool stop_ = false;
  std::thread worker_;
};

}  // namespace icgm::nodelets
