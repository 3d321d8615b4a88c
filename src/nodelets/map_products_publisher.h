// Publishes a learned map's people-free products for rviz (core/map_export/map_products.h):
// the occupancy grid (nav_msgs/OccupancyGrid) on `map/occupancy_grid` and the voxel-filtered
// static cloud (PointCloud2, x y z rgb) on `map/static_cloud`, both latched. Building them takes
// seconds on a large map, so it runs on a worker thread from a copy of the map; a request made
// while one is being built replaces any waiting one (the latest map wins).
#pragma once

#include <condition_variable>
#include <memory>
#include <mutex>
#include <string>
#include <thread>

#include <ros/ros.h>

#include "core/map/hybrid_map.h"
#include "core/map/map_export_options.h"

namespace icgm::nodelets {

class MapProductsPublisher {
 public:
  MapProductsPublisher(ros::NodeHandle& nh, const std::string& map_frame,
                       const MapExportOptions& options);
  ~MapProductsPublisher();

  // Builds and publishes the products of `map` (copied) stamped `stamp`.
  void Request(const HybridMap& map, ros::Time stamp);

 private:
  void Work();

  ros::Publisher grid_pub_, cloud_pub_;
  std::string map_frame_;
  MapExportOptions options_;
  std::mutex mutex_;
  std::condition_variable wake_;
  std::unique_ptr<HybridMap> pending_;
  ros::Time pending_stamp_;
  bool stop_ = false;
  std::thread worker_;
};

}  // namespace icgm::nodelets
