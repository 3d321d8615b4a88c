#include "ros_bridge/obstacle_grid_msgs.h"

#include <cmath>

#include "ros_bridge/conversions.h"

namespace icgm::ros_bridge {

nav_msgs::OccupancyGrid ToOccupancyGridMsg(const OccupancyGridData& grid,
                                           const std::string& frame_id, Time stamp) {
  nav_msgs::OccupancyGrid m;
  m.header.frame_id = frame_id;
  m.header.stamp = ToRos(stamp);
  m.info.map_load_time = m.header.stamp;
  m.info.resolution = static_cast<float>(grid.resolution_m);
  m.info.width = static_cast<uint32_t>(grid.width);
  m.info.height = static_cast<uint32_t>(grid.height);
  m.info.origin.position.x = grid.origin_x_m;
  m.info.origin.position.y = grid.origin_y_m;
  m.info.origin.orientation.w = 1.0;
  m.data = grid.data;
  return m;
}

bool FromOccupancyGridMsg(const nav_msgs::OccupancyGrid& msg, OccupancyGridData* out) {
  const auto& q = msg.info.origin.orientation;
  const bool unrotated = std::abs(q.x) < 1e-9 && std::abs(q.y) < 1e-9 && std::abs(q.z) < 1e-9;
  if (!unrotated || msg.data.size() != static_cast<size_t>(msg.info.width) * msg.info.height) {
    return false;
  }
  out->origin_x_m = msg.info.origin.position.x;
  out->origin_y_m = msg.info.origin.position.y;
  out->resolution_m = msg.info.resolution;
  out->width = static_cast<int>(msg.info.width);
  out->height = static_cast<int>(msg.info.height);
  out->data = msg.data;
  return true;
}

}  // namespace icgm::ros_bridge
