// People-free map products (core/map/occupancy_grid.h, core/map/map_points.h) <-> messages:
// the occupancy grid as nav_msgs/OccupancyGrid (same layout: row-major from the lowest y,
// -1 / 0 / 100; origin = the lower-left cell's corner, yaw 0) and the static map points as a
// coloured sensor_msgs/PointCloud2 (x y z rgb) in the map frame.
#pragma once

#include <string>
#include <vector>

#include <nav_msgs/OccupancyGrid.h>
#include <sensor_msgs/PointCloud2.h>

#include "core/common/status.h"
#include "core/common/time.h"
#include "core/map/map_points.h"
#include "core/map/occupancy_grid.h"

namespace icgm::ros_bridge {

nav_msgs::OccupancyGrid ToOccupancyGridMsg(const OccupancyGrid& grid, const std::string& frame_id,
                                           Time stamp);
// Fails on a rotated origin or a data size that does not match width x height.
Status FromOccupancyGridMsg(const nav_msgs::OccupancyGrid& msg, OccupancyGrid* grid);

sensor_msgs::PointCloud2 ToMapPointsCloud(const std::vector<MapPoint>& points,
                                          const std::string& frame_id, Time stamp);
// Positions and colours (the keyframe ids and pixels are not carried); fails without x y z rgb.
Status FromMapPointsCloud(const sensor_msgs::PointCloud2& cloud, std::vector<MapPoint>* points);

}  // namespace icgm::ros_bridge
