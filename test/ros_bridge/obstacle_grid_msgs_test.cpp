// The navigator's obstacle grid through the map's occupancy-grid conversions
// (map_product_msgs.h): the grid the navigation nodelet publishes.
#include "ros_bridge/map_product_msgs.h"

#include <gtest/gtest.h>

#include "core/nav/obstacle_grid.h"
#include "ros_bridge/conversions.h"

namespace icgm::ros_bridge {
namespace {

TEST(ObstacleGridMsgsTest, RoundTripOfAGridWithAnObstacle) {
  // A real grid: one obstacle point 1 m ahead of a robot at (2, 3).
  ObstacleGridOptions options;
  options.size_m = 2.0;
  options.resolution_m = 0.1;
  options.min_points_per_cell = 1;
  ObstacleGrid grid(options);
  grid.AddPoints(Time::FromSeconds(1), {2.0, 3.0}, {{2.55, 3.05}});
  const OccupancyGrid data = grid.Export();
  ASSERT_GT(data.width, 0);
  const nav_msgs::OccupancyGrid msg = ToOccupancyGridMsg(data, "map", Time::FromSeconds(1));
  EXPECT_EQ(msg.header.frame_id, "map");
  EXPECT_EQ(FromRos(msg.header.stamp), Time::FromSeconds(1));
  EXPECT_EQ(msg.info.width, static_cast<uint32_t>(data.width));
  EXPECT_EQ(msg.info.height, static_cast<uint32_t>(data.height));
  EXPECT_FLOAT_EQ(msg.info.resolution, 0.1f);
  // The obstacle's cell, found from the message's own geometry, holds 100.
  const int col = static_cast<int>((2.55 - msg.info.origin.position.x) / msg.info.resolution);
  const int row = static_cast<int>((3.05 - msg.info.origin.position.y) / msg.info.resolution);
  EXPECT_EQ(msg.data[row * msg.info.width + col], 100);

  OccupancyGrid back;
  ASSERT_TRUE(FromOccupancyGridMsg(msg, &back).ok());
  EXPECT_DOUBLE_EQ(back.origin_m.x(), data.origin_m.x());
  EXPECT_DOUBLE_EQ(back.origin_m.y(), data.origin_m.y());
  EXPECT_NEAR(back.resolution_m, data.resolution_m, 1e-7);
  EXPECT_EQ(back.width, data.width);
  EXPECT_EQ(back.height, data.height);
  EXPECT_EQ(back.data, data.data);
}

TEST(ObstacleGridMsgsTest, RefusesInconsistentMessages) {
  nav_msgs::OccupancyGrid msg;
  msg.info.width = 3;
  msg.info.height = 2;
  msg.info.origin.orientation.w = 1.0;
  msg.data.assign(5, 0);  // one cell short
  OccupancyGrid out;
  out.width = 7;
  EXPECT_FALSE(FromOccupancyGridMsg(msg, &out).ok());
  EXPECT_EQ(out.width, 7);
  msg.data.assign(6, 0);
  msg.info.origin.orientation.z = 0.7071;
  msg.info.origin.orientation.w = 0.7071;
  EXPECT_FALSE(FromOccupancyGridMsg(msg, &out).ok());
  msg.info.origin.orientation.z = 0.0;
  msg.info.origin.orientation.w = 1.0;
  EXPECT_TRUE(FromOccupancyGridMsg(msg, &out).ok());
  EXPECT_EQ(out.width, 3);
}

}  // namespace
}  // namespace icgm::ros_bridge
