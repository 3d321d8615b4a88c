// Localization through the map-building nodelet: a learned map loaded with ~mode localization,
// the bag replayed from part-way round with the wheel odometry restarted at an arbitrary pose.
// The robot must relocalize by place recognition (map -> odom undoes the restart), the learned
// map must stay as it was (no keyframes added, its file unchanged, a save onto it refused), an
// unknown mode must be refused, and /initialpose must set the pose. The loaded map's people-free
// occupancy grid and static cloud must be published (latched) as the core builds them, with the
// cells the robot drove through free.
#include <cstdio>
#include <fstream>
#include <iterator>
#include <string>

#include <geometry_msgs/PoseWithCovarianceStamped.h>
#include <gtest/gtest.h>
#include <icgm_slam/SaveMap.h>
#include <icgm_slam/SetMapMode.h>
#include <nav_msgs/OccupancyGrid.h>
#include <nav_msgs/Odometry.h>
#include <sensor_msgs/PointCloud2.h>
#include <ros/service.h>
#include <tf2_ros/buffer.h>
#include <tf2_ros/transform_listener.h>

#include "bag_replayer.h"
#include "core/map/map_export_options.h"
#include "core/map/map_store.h"
#include "core/map_export/map_products.h"
#include "map_products_check.h"
#include "ros_bridge/conversions.h"
#include "ros_bridge/map_product_msgs.h"

namespace icgm_slam::test {
namespace {

std::string ReadBytes(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
}

icgm::Pose3 LookUp(tf2_ros::Buffer& tf, const std::string& parent, const std::string& child) {
  return icgm::ros_bridge::FromTransformMsg(
      tf.lookupTransform(parent, child, ros::Time(0)).transform);
}

// map -> base_link as the latest map -> odom times the latest odom -> base_link (the replay has
// no /clock, so the two are stamped on different clocks and tf cannot chain them itself).
icgm::Pose3 MapBase(tf2_ros::Buffer& tf) {
  return LookUp(tf, "map", "odom") * LookUp(tf, "odom", "base_link");
}

TEST(LocalizationPipeline, RelocalizesOnTheLearnedMapWithoutWritingIt) {
  ros::NodeHandle nh;
  ros::NodeHandle pnh("~");
  ReplayOptions options;
  std::string map_path;
  ASSERT_TRUE(pnh.getParam("bag", options.bag_path));
  ASSERT_TRUE(pnh.getParam("map", map_path));
  pnh.param("first_frame", options.first_frame, 60);
  pnh.param("max_frames", options.max_frames, 30);
  options.odom_offset =
      icgm::MakePose({4.0, -3.0, 0.0}, icgm::Quat(Eigen::AngleAxisd(2.0, icgm::Vec3::UnitZ())));
  const std::string learned = ReadBytes(map_path);
  ASSERT_FALSE(learned.empty()) << "no map at " << map_path;
  const int learned_keyframes = icgm::LoadMap(map_path).size();
  // Lock-step replay: registration needs a reference (1) and waits for the wheel sample after
  // a frame's stamp + 50 ms, which the replay sends only after the next frame's images (2).
  const int delay = 3;

  int odom_count = 0;
  ros::Subscriber odom_sub = nh.subscribe<nav_msgs::Odometry>(
      "/icgm/odom", 200, [&](const nav_msgs::Odometry::ConstPtr&) { ++odom_count; });
  tf2_ros::Buffer tf;
  tf2_ros::TransformListener listener(tf);

  // An unknown mode is refused, and the nodelet stays in localization.
  icgm_slam::SetMapMode mode;
  mode.request.mode = "navigation";
  ASSERT_TRUE(ros::service::waitForService("/map_builder/set_mode", 10000));
  ASSERT_TRUE(ros::service::call("/map_builder/set_mode", mode));
  EXPECT_FALSE(mode.response.success);
  EXPECT_NE(mode.response.message.find("neither mapping nor localization"), std::string::npos);

  const int frames = ReplayBag(nh, options, [&](int i) { return odom_count >= i + 1 - delay; });
  ASSERT_GE(frames, options.max_frames);
  const ros::WallTime end = ros::WallTime::now() + ros::WallDuration(2.0);
  while (ros::WallTime::now() < end) {
    ros::spinOnce();
    ros::WallDuration(0.02).sleep();
  }

  // The map was built with the wheels' own odometry frame; the replay restarted it at
  // odom_offset, so a relocalized map -> odom is about odom_offset^-1.
  ASSERT_TRUE(tf.canTransform("map", "odom", ros::Time(0), ros::Duration(2.0)));
  const icgm::Pose3 map_odom = LookUp(tf, "map", "odom");
  const icgm::Pose3 err = icgm::Between(options.odom_offset.inverse(), map_odom);
  std::printf("map -> odom off the restart by %.3f m / %.2f deg\n", icgm::TranslationNorm(err),
              icgm::RotationAngleRad(err) * 180 / M_PI);
  EXPECT_LT(icgm::TranslationNorm(err), 0.3) << "not relocalized";
  EXPECT_LT(icgm::RotationAngleRad(err) * 180 / M_PI, 5.0);

  // The learned map is untouched, and saving onto it is refused.
  icgm_slam::SaveMap save;
  save.request.path = map_path;
  ASSERT_TRUE(ros::service::call("/map_builder/save_map", save));
  EXPECT_FALSE(save.response.success);
  std::printf("save onto the learned map: %s\n", save.response.message.c_str());
  EXPECT_EQ(ReadBytes(map_path), learned);
  EXPECT_EQ(icgm::LoadMap(map_path).size(), learned_keyframes);

  // /initialpose (rviz "2D Pose Estimate"): the base 1 m ahead of where the map puts it.
  const icgm::Pose3 map_base = MapBase(tf);
  geometry_msgs::PoseWithCovarianceStamped initial;
  initial.header.frame_id = "map";
  initial.header.stamp = ros::Time::now();
  initial.pose.pose = icgm::ros_bridge::ToPoseMsg(
      icgm::MakePose({1.0, 0.0, 0.0}, icgm::Quat::Identity()) * map_base);
  ros::Publisher initial_pub =
      nh.advertise<geometry_msgs::PoseWithCovarianceStamped>("/initialpose", 1, true);
  initial_pub.publish(initial);
  bool moved = false;
  const ros::WallTime until = ros::WallTime::now() + ros::WallDuration(5.0);
  while (!moved && ros::WallTime::now() < until) {
    ros::spinOnce();
    ros::WallDuration(0.05).sleep();
    const icgm::Pose3 now = MapBase(tf);
    moved = std::abs((now.translation() - map_base.translation()).norm() - 1.0) < 0.05;
  }
  EXPECT_TRUE(moved) << "map -> odom did not follow /initialpose";
}

TEST(LocalizationPipeline, PublishesTheLearnedMapsGridAndStaticCloud) {
  ros::NodeHandle nh;
  ros::NodeHandle pnh("~");
  std::string map_path, export_config;
  ASSERT_TRUE(pnh.getParam("map", map_path));
  ASSERT_TRUE(pnh.getParam("map_export_config", export_config));
  MapProductsListener products;
  // Latched, built once the map is loaded (at the first camera_info of the first test's replay).
  ASSERT_TRUE(products.Wait(120.0)) << "no /icgm/map/occupancy_grid or /icgm/map/static_cloud";
  const nav_msgs::OccupancyGrid::ConstPtr& grid = products.grid();
  EXPECT_EQ(grid->header.frame_id, "map");
  EXPECT_EQ(products.cloud()->header.frame_id, "map");

  // The same products as the core builds from the map file.
  const icgm::HybridMap map = icgm::LoadMap(map_path);
  icgm::MapProducts expected;
  ASSERT_TRUE(
      icgm::BuildMapProducts(map, icgm::LoadMapExportOptions(export_config), &expected).ok());
  ExpectProductsAsTheCore(products, expected, 0, 0.0);
  EXPECT_GT(expected.cloud.size(), 1000u);
  const size_t occupied = expected.grid.Count(icgm::OccupancyGrid::kOccupied);
  EXPECT_GT(occupied, 50u);

  // Ground truth: the robot drove where the keyframes were taken, so those cells are free.
  icgm::OccupancyGrid published;
  ASSERT_TRUE(icgm::ros_bridge::FromOccupancyGridMsg(*grid, &published).ok());
  int free = 0, total = 0;
  for (const auto& kf : map.keyframes()) {
    int x = 0, y = 0;
    ++total;
    if (published.CellOf(kf.global_pose.translation().head<2>(), &x, &y)) {
      free += published.at(x, y) == icgm::OccupancyGrid::kFree ? 1 : 0;
    }
  }
  std::printf("map products: grid %d x %d, %zu occupied; static cloud %zu points; %d of %d "
              "keyframe positions free\n",
              expected.grid.width, expected.grid.height, occupied, expected.cloud.size(), free,
              total);
  EXPECT_GE(free, 0.9 * total);
}

}  // namespace
}  // namespace icgm_slam::test
