// Test helper: the map builder's latched map products (/icgm/map/occupancy_grid,
// /icgm/map/static_cloud) as a subscriber gets them, compared with the core's products
// (BuildMapProducts) of the same map.
#pragma once

#include <cstdio>

#include <gtest/gtest.h>
#include <nav_msgs/OccupancyGrid.h>
#include <ros/ros.h>
#include <sensor_msgs/PointCloud2.h>

#include "core/map_export/map_products.h"

namespace icgm_slam::test {

class MapProductsListener {
 public:
  MapProductsListener() {
    ros::NodeHandle nh;
    grid_sub_ = nh.subscribe<nav_msgs::OccupancyGrid>(
        "/icgm/map/occupancy_grid", 1,
        [this](const nav_msgs::OccupancyGrid::ConstPtr& m) { grid_ = m; });
    cloud_sub_ = nh.subscribe<sensor_msgs::PointCloud2>(
        "/icgm/map/static_cloud", 1,
        [this](const sensor_msgs::PointCloud2::ConstPtr& m) { cloud_ = m; });
  }
  // Spins until both products arrived (true) or `timeout_s` of wall time passed.
  bool Wait(double timeout_s) {
    const ros::WallTime until = ros::WallTime::now() + ros::WallDuration(timeout_s);
    while ((!grid_ || !cloud_) && ros::WallTime::now() < until) {
      ros::spinOnce();
      ros::WallDuration(0.05).sleep();
    }
    return grid_ && cloud_;
  }
  void Reset() {
    grid_.reset();
    cloud_.reset();
  }
  const nav_msgs::OccupancyGrid::ConstPtr& grid() const { return grid_; }
  const sensor_msgs::PointCloud2::ConstPtr& cloud() const { return cloud_; }
  size_t cloud_points() const { return static_cast<size_t>(cloud_->width) * cloud_->height; }

 private:
  ros::Subscriber grid_sub_, cloud_sub_;
  nav_msgs::OccupancyGrid::ConstPtr grid_;
  sensor_msgs::PointCloud2::ConstPtr cloud_;
};

// The received products against the core's: the grid's size within `grid_cells` cells and the
// cloud's size within `cloud_share` of the core's; with both 0 the grid must be equal (size,
// resolution, origin, cells) and the cloud as large.
inline void ExpectProductsAsTheCore(const MapProductsListener& received,
                                    const icgm::MapProducts& expected, int grid_cells,
                                    double cloud_share) {
  ASSERT_TRUE(received.grid() && received.cloud());
  const nav_msgs::OccupancyGrid& grid = *received.grid();
  std::printf("map products: grid %u x %u (core %d x %d), static cloud %zu points (core %zu)\n",
              grid.info.width, grid.info.height, expected.grid.width, expected.grid.height,
              received.cloud_points(), expected.cloud.size());
  EXPECT_NEAR(static_cast<int>(grid.info.width), expected.grid.width, grid_cells);
  EXPECT_NEAR(static_cast<int>(grid.info.height), expected.grid.height, grid_cells);
  EXPECT_NEAR(static_cast<double>(received.cloud_points()),
              static_cast<double>(expected.cloud.size()), cloud_share * expected.cloud.size());
  if (grid_cells == 0 && cloud_share == 0.0) {
    EXPECT_NEAR(grid.info.resolution, expected.grid.resolution_m, 1e-6);
    EXPECT_NEAR(grid.info.origin.position.x, expected.grid.origin_m.x(), 1e-6);
    EXPECT_NEAR(grid.info.origin.position.y, expected.grid.origin_m.y(), 1e-6);
    EXPECT_TRUE(grid.data == expected.grid.data) << "the published grid differs from the core's";
  }
}

}  // namespace icgm_slam::test
