#include "nodelets/map_products_publisher.h"

#include <nav_msgs/OccupancyGrid.h>
#include <sensor_msgs/PointCloud2.h>

#include "core/map_export/map_products.h"
#include "ros_bridge/conversions.h"
#include "ros_bridge/map_product_msgs.h"

namespace icgm::nodelets {

MapProductsPublisher::MapProductsPublisher(ros::NodeHandle& nh, ros::NodeHandle& pnh,
                                           const std::string& map_frame,
                                           const MapExportOptions& options, MapSource map)
    : map_frame_(map_frame), options_(options), map_(std::move(map)) {
  const ros::SubscriberStatusCallback connected = [this](const ros::SingleSubscriberPublisher&) {
    Connected();
  };
  grid_pub_ = nh.advertise<nav_msgs::OccupancyGrid>("map/occupancy_grid", 1, connected,
                                                    ros::SubscriberStatusCallback(),
                                                    ros::VoidConstPtr(), true);
  cloud_pub_ = nh.advertise<sensor_msgs::PointCloud2>("map/static_cloud", 1, connected,
                                                      ros::SubscriberStatusCallback(),
                                                      ros::VoidConstPtr(), true);
  request_srv_ = pnh.advertiseService("build_map_products", &MapProductsPublisher::RequestCb, this);
  worker_ = std::thread([this] { Work(); });
}

MapProductsPublisher::~MapProductsPublisher() {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    stop_ = true;
  }
  wake_.notify_all();
  worker_.join();
}

bool MapProductsPublisher::Wanted() const {
  return grid_pub_.getNumSubscribers() > 0 || cloud_pub_.getNumSubscribers() > 0;
}

void MapProductsPublisher::OnSave() {
  if (Wanted()) {
    Build("save");
  } else {
    stale_ = true;
  }
}

void MapProductsPublisher::Connected() {
  if (stale_) Build("first subscriber after a save");
}

bool MapProductsPublisher::RequestCb(std_srvs::Trigger::Request&,
                                     std_srvs::Trigger::Response& res) {
  res.success = Build("request");
  res.message = res.success ? "building the map products" : "no map yet";
  return true;
}

bool MapProductsPublisher::Build(const char* why) {
  ros::Time stamp;
  const HybridMap* map = map_(&stamp);
  if (!map || map->empty()) return false;
  stale_ = false;
  auto copy = std::make_unique<HybridMap>(*map);
  ROS_DEBUG("map builder: map products of %d keyframes requested (%s)", copy->size(), why);
  {
    std::lock_guard<std::mutex> lock(mutex_);
    pending_ = std::move(copy);
    pending_stamp_ = stamp;
  }
  wake_.notify_all();
  return true;
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
