// The navigator's obstacle grid (core/nav/obstacle_grid.h) <-> nav_msgs/OccupancyGrid for rviz.
// OccupancyGridData is already laid out as the message carries it (row-major from the origin
// cell, -1 unknown, 0 free, 99 inflated, 100 obstacle), so both directions copy.
#pragma once

#include <string>

#include <nav_msgs/OccupancyGrid.h>

#include "core/common/time.h"
#include "core/nav/obstacle_grid.h"

namespace icgm::ros_bridge {

// The grid lies on the floor (z = 0) of `frame_id`, unrotated.
nav_msgs::OccupancyGrid ToOccupancyGridMsg(const OccupancyGridData& grid,
                                           const std::string& frame_id, Time stamp);
// Fails (false, `out` untouched) when data does not hold width x height cells or the grid is
// rotated (the core grid is axis-aligned).
bool FromOccupancyGridMsg(const nav_msgs::OccupancyGrid& msg, OccupancyGridData* out);

}  // namespace icgm::ros_bridge
