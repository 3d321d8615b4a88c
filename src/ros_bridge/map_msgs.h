// Hybrid map (core) -> rviz messages: the graph as a MarkerArray (keyframe nodes, odometry and
// loop-closure links), the map cloud (PointCloud2 of every keyframe's robust 3D points in the
// map frame) and the keyframe path.
#pragma once

#include <string>

#include <nav_msgs/Path.h>
#include <sensor_msgs/PointCloud2.h>
#include <visualization_msgs/MarkerArray.h>

#include "core/common/time.h"
#include "core/map/hybrid_map.h"

namespace icgm::ros_bridge {

std_msgs::ColorRGBA Rgba(float r, float g, float b, float a = 1.f);
// A marker with header, namespace, type and a uniform scale set, action ADD, identity pose.
visualization_msgs::Marker MakeMarker(const std::string& frame_id, Time stamp, const char* ns,
                                      int type, double scale);

visualization_msgs::MarkerArray ToGraphMarkers(const HybridMap& map, const std::string& frame_id,
                                               Time stamp);
// Points farther than max_range_m from their keyframe are left out (depth noise grows fast).
sensor_msgs::PointCloud2 ToMapCloud(const HybridMap& map, const std::string& frame_id, Time stamp,
                                    double max_range_m = 4.0);
nav_msgs::Path ToKeyframePath(const HybridMap& map, const std::string& frame_id, Time stamp);

}  // namespace icgm::ros_bridge
