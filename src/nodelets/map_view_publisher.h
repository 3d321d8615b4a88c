// The map for rviz (latched): keyframe graph (MarkerArray) on `map/graph`, feature cloud
// (PointCloud2) on `map/cloud`, keyframe path on `map/path`; each built only while someone
// listens.
#pragma once

#include <string>

#include <ros/ros.h>

#include "core/map/hybrid_map.h"

namespace icgm::nodelets {

class MapViewPublisher {
 public:
  MapViewPublisher(ros::NodeHandle& nh, std::string map_frame);
  void Publish(const HybridMap& map, const ros::Time& stamp);

 private:
  std::string map_frame_;
  ros::Publisher graph_pub_, cloud_pub_, path_pub_;
};

}  // namespace icgm::nodelets
