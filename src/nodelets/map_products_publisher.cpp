#include "nodelets/map_products_publisher.h"

#include <nav_msgs/OccupancyGrid.h>
#include <sensor_msgs/PointCloud2.h>

#include "core/map_export/map_products.h"
#include "ros_bridge/conversions.h"
#include "ros_bridge/map_product_msgs.h"

namespace icgm::nodelets {

MapProductsPublisher::MapProductsPublisher(ros::NodeHandle& nh, const std::string& map_frame,
                                           const MapExportOptions& options)
    : grid_pub_(nh.advertise<nav_msgs::OccupancyGrid>("map/occupancy_grid", 1, true)),
      cloud_pub_(nh.advertise<sensor_msgs::PointCloud2>("map/static_cloud", 1, true)),
      map_frame_(map_frame),
      options_(options),
      worker_([this] { Work(); }) {}

MapProductsPublisher::~MapProductsPublisher() {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    stop_ = true;
  }
  wake_.notify_all();
  worker_.join();
}

void MapProductsPublisher::Request(const HybridMap& map, ros::Time stamp) {
  auto copy = std::make_unique<HybridMap>(map);
  {
    std::lock_guard<std::mutex> lock(mutex_);
    pending_ = std::move(copy);
    pending_stamp_ = stamp;
  }
  wake_.notify_all();
}

void MapProductsPublisher::Work() {
  while (true) {
    std::unique_ptr<HybridMap> map;
    ros::Time stamp;
    {
      std::unique_lock<std::mutex> lock(mutex_);
      wake_.wait(lock, [this] { return stop_ || pending_; });
      if (stop_) return;
      map = std::move(pending_);
      stamp = pending_stamp_;
    }
    const ros::WallTime start = ros::WallTime::now();
    MapProducts products;
    Status s = Status::Ok();
    try {
      s = BuildMapProducts(*map, options_, &products);
    } catch (const std::exception& e) {
      s = Status::Error(e.what());
    }
    if (!s.ok()) {
      ROS_WARN("map builder: no map products: %s", s.reason().c_str());
      continue;
    }
    const Time t = ros_bridge::FromRos(stamp);
    grid_pub_.publish(ros_bridge::ToOccupancyGridMsg(products.grid, map_frame_, t));
    cloud_pub_.publish(ros_bridge::ToMapPointsCloud(products.cloud, map_frame_, t));
    ROS_INFO("map builder: map products of %d keyframes in %.1f s: grid %d x %d (%zu occupied), "
             "static cloud %zu points (%zu of %zu map points static)",
             map->size(), (ros::WallTime::now() - start).toSec(), products.grid.width,
             products.grid.height, products.grid.Count(OccupancyGrid::kOccupied),
             products.cloud.size(), products.stats.kept, products.stats.points);
  }
}

}  // namespace icgm::nodelets
