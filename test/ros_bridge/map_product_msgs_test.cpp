// Map products <-> messages round trip: the occupancy grid cell for cell with its geometry, the
// static cloud point for point with colours.
#include <gtest/gtest.h>

#include <sensor_msgs/point_cloud2_iterator.h>

#include "ros_bridge/map_product_msgs.h"

namespace icgm::ros_bridge {
namespace {

TEST(MapProductMsgsTest, OccupancyGridRoundTrip) {
  OccupancyGrid grid;
  grid.resolution_m = 0.05;
  grid.origin_m = Eigen::Vector2d(-1.25, 3.5);
  grid.width = 7;
  grid.height = 4;
  for (int i = 0; i < grid.width * grid.height; ++i) {
    grid.data.push_back(i % 3 == 0 ? OccupancyGrid::kUnknown
                                   : (i % 3 == 1 ? OccupancyGrid::kFree : OccupancyGrid::kOccupied));
  }
  const nav_msgs::OccupancyGrid msg = ToOccupancyGridMsg(grid, "map", Time::FromSeconds(12.5));
  EXPECT_EQ(msg.header.frame_id, "map");
  EXPECT_DOUBLE_EQ(msg.header.stamp.toSec(), 12.5);
  EXPECT_EQ(msg.info.width, 7u);
  EXPECT_EQ(msg.data[1 * 7 + 2], grid.at(2, 1));  // row-major from the lowest y, as the core
  OccupancyGrid back;
  ASSERT_TRUE(FromOccupancyGridMsg(msg, &back).ok());
  EXPECT_EQ(back.data, grid.data);
  EXPECT_EQ(back.width, grid.width);
  EXPECT_EQ(back.height, grid.height);
  EXPECT_NEAR(back.resolution_m, grid.resolution_m, 1e-7);  // float in the message
  EXPECT_EQ(back.origin_m, grid.origin_m);

  nav_msgs::OccupancyGrid short_data = msg;
  short_data.data.pop_back();
  EXPECT_FALSE(FromOccupancyGridMsg(short_data, &back).ok());
  nav_msgs::OccupancyGrid rotated = msg;
  rotated.info.origin.orientation.z = 0.7071;
  rotated.info.origin.orientation.w = 0.7071;
  EXPECT_FALSE(FromOccupancyGridMsg(rotated, &back).ok());
}

TEST(MapProductMsgsTest, CloudRoundTrip) {
  std::vector<MapPoint> points;
  for (int i = 0; i < 50; ++i) {
    MapPoint p;
    p.position_m = Eigen::Vector3f(0.1f * i, -0.2f * i, 1.0f + 0.01f * i);
    p.bgr = cv::Vec3b(static_cast<uint8_t>(i), static_cast<uint8_t>(2 * i), 200);
    points.push_back(p);
  }
  const sensor_msgs::PointCloud2 cloud = ToMapPointsCloud(points, "map", Time::FromSeconds(3.0));
  EXPECT_EQ(cloud.width * cloud.height, 50u);
  std::vector<MapPoint> back;
  ASSERT_TRUE(FromMapPointsCloud(cloud, &back).ok());
  ASSERT_EQ(back.size(), points.size());
  for (size_t i = 0; i < points.size(); ++i) {
    EXPECT_EQ(back[i].position_m, points[i].position_m) << i;
    EXPECT_EQ(back[i].bgr, points[i].bgr) << i;
  }
  sensor_msgs::PointCloud2 no_colour;
  sensor_msgs::PointCloud2Modifier(no_colour).setPointCloud2FieldsByString(1, "xyz");
  EXPECT_FALSE(FromMapPointsCloud(no_colour, &back).ok());
}

}  // namespace
}  // namespace icgm::ros_bridge
