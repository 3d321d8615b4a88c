#include "nodelets/map_view_publisher.h"

#include <nav_msgs/Path.h>
#include <sensor_msgs/PointCloud2.h>
#include <visualization_msgs/MarkerArray.h>

#include "ros_bridge/conversions.h"
#include "ros_bridge/map_msgs.h"

namespace icgm::nodelets {

MapViewPublisher::MapViewPublisher(ros::NodeHandle& nh, std::string map_frame)
    : map_frame_(std::move(map_frame)),
      graph_pub_(nh.advertise<visualization_msgs::MarkerArray>("map/graph", 1, true)),
      cloud_pub_(nh.advertise<sensor_msgs::PointCloud2>("map/cloud", 1, true)),
      path_pub_(nh.advertise<nav_msgs::Path>("map/path", 1, true)) {}

void MapViewPublisher::Publish(const HybridMap& map, const ros::Time& ros_stamp) {
  const Time stamp = ros_bridge::FromRos(ros_stamp);
  if (graph_pub_.getNumSubscribers() > 0) {
    graph_pub_.publish(ros_bridge::ToGraphMarkers(map, map_frame_, stamp));
  }
  if (cloud_pub_.getNumSubscribers() > 0) {
    cloud_pub_.publish(ros_bridge::ToMapCloud(map, map_frame_, stamp));
  }
  if (path_pub_.getNumSubscribers() > 0) {
    path_pub_.publish(ros_bridge::ToKeyframePath(map, map_frame_, stamp));
  }
}

}  // namespace icgm::nodelets
