#include "ros_bridge/map_product_msgs.h"

#include <cmath>

#include <sensor_msgs/point_cloud2_iterator.h>

#include "ros_bridge/conversions.h"

namespace icgm::ros_bridge {

nav_msgs::OccupancyGrid ToOccupancyGridMsg(const OccupancyGrid& grid, const std::string& frame_id,
                                           Time stamp) {
  nav_msgs::OccupancyGrid msg;
  msg.header.frame_id = frame_id;
  msg.header.stamp = ToRos(stamp);
  msg.info.map_load_time = msg.header.stamp;
  msg.info.resolution = static_cast<float>(grid.resolution_m);
  msg.info.width = static_cast<uint32_t>(grid.width);
  msg.info.height = static_cast<uint32_t>(grid.height);
  msg.info.origin.position.x = grid.origin_m.x();
  msg.info.origin.position.y = grid.origin_m.y();
  msg.info.origin.orientation.w = 1.0;
  msg.data.assign(grid.data.begin(), grid.data.end());
  return msg;
}

Status FromOccupancyGridMsg(const nav_msgs::OccupancyGrid& msg, OccupancyGrid* grid) {
  const auto& q = msg.info.origin.orientation;
  if (std::abs(q.x) > 1e-9 || std::abs(q.y) > 1e-9 || std::abs(q.z) > 1e-9) {
    return Status::Error("occupancy grid with a rotated origin is not supported");
  }
  if (msg.data.size() != static_cast<size_t>(msg.info.width) * msg.info.height) {
    return Status::Error("occupancy grid data has " + std::to_string(msg.data.size()) +
                         " cells, expected " + std::to_string(msg.info.width) + " x " +
                         std::to_string(msg.info.height));
  }
  grid->resolution_m = msg.info.resolution;
  grid->origin_m = Eigen::Vector2d(msg.info.origin.position.x, msg.info.origin.position.y);
  grid->width = static_cast<int>(msg.info.width);
  grid->height = static_cast<int>(msg.info.height);
  grid->data.assign(msg.data.begin(), msg.data.end());
  return Status::Ok();
}

sensor_msgs::PointCloud2 ToMapPointsCloud(const std::vector<MapPoint>& points,
                                          const std::string& frame_id, Time stamp) {
  sensor_msgs::PointCloud2 cloud;
  cloud.header.frame_id = frame_id;
  cloud.header.stamp = ToRos(stamp);
  sensor_msgs::PointCloud2Modifier modifier(cloud);
  modifier.setPointCloud2FieldsByString(2, "xyz", "rgb");
  modifier.resize(points.size());
  sensor_msgs::PointCloud2Iterator<float> x(cloud, "x"), y(cloud, "y"), z(cloud, "z");
  sensor_msgs::PointCloud2Iterator<uint8_t> r(cloud, "r"), g(cloud, "g"), b(cloud, "b");
  for (const MapPoint& p : points) {
    *x = p.position_m.x();
    *y = p.position_m.y();
    *z = p.position_m.z();
    *b = p.bgr[0];
    *g = p.bgr[1];
    *r = p.bgr[2];
    ++x, ++y, ++z, ++r, ++g, ++b;
  }
  return cloud;
}

Status FromMapPointsCloud(const sensor_msgs::PointCloud2& cloud, std::vector<MapPoint>* points) {
  bool has[4] = {false, false, false, false};
  for (const auto& f : cloud.fields) {
    has[0] |= f.name == "x";
    has[1] |= f.name == "y";
    has[2] |= f.name == "z";
    has[3] |= f.name == "rgb";
  }
  if (!(has[0] && has[1] && has[2] && has[3])) {
    return Status::Error("cloud lacks one of the fields x y z rgb");
  }
  points->clear();
  points->reserve(static_cast<size_t>(cloud.width) * cloud.height);
  sensor_msgs::PointCloud2ConstIterator<float> x(cloud, "x"), y(cloud, "y"), z(cloud, "z");
  sensor_msgs::PointCloud2ConstIterator<uint8_t> r(cloud, "r"), g(cloud, "g"), b(cloud, "b");
  for (; x != x.end(); ++x, ++y, ++z, ++r, ++g, ++b) {
    MapPoint p;
    p.position_m = Eigen::Vector3f(*x, *y, *z);
    p.bgr = cv::Vec3b(*b, *g, *r);
    points->push_back(p);
  }
  return Status::Ok();
}

}  // namespace icgm::ros_bridge
