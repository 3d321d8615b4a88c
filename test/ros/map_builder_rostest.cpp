// Replays two laps of a simulated loop through the whole nodelet pipeline (features ->
// registration -> fusion -> map builder) and checks the hybrid map: loop closures are found on
// the second lap, every loop link is a true constraint (its relative pose agrees with ground
// truth and joins views of the same place), wheel-odometry links sit beside the visual steps,
// map -> odom is on tf, and the save service writes a map that loads with the same keyframes.
#include <cstdio>
#include <filesystem>
#include <optional>

#include <gtest/gtest.h>
#include <icgm_slam/SaveMap.h>
#include <nav_msgs/Odometry.h>
#include <ros/service.h>
#include <std_srvs/Trigger.h>
#include <tf2_ros/buffer.h>
#include <tf2_ros/transform_listener.h>
#include <visualization_msgs/MarkerArray.h>

#include "bag_replayer.h"
#include "core/map/map_store.h"
#include "core/map_export/map_products.h"
#include "map_products_check.h"
#include "ros_bridge/bag_reader.h"
#include "ros_bridge/conversions.h"

namespace icgm_slam::test {
namespace {

// The map products after a save made while nobody listened to them: the first subscriber gets
// them (built then), equal to the core's products of the saved map (up to the map file's
// rounding); `~build_map_products` builds them again on request.
void CheckMapProductsOnDemand(const icgm::HybridMap& saved) {
  MapProductsListener products;
  ASSERT_TRUE(products.Wait(180.0)) << "no /icgm/map/occupancy_grid or /icgm/map/static_cloud "
                                       "for the first subscriber after a save";
  icgm::MapProducts expected;
  ASSERT_TRUE(icgm::BuildMapProducts(saved, icgm::MapExportOptions(), &expected).ok());
  ExpectProductsAsTheCore(products, expected, 1, 0.02);
  EXPECT_GT(expected.cloud.size(), 100u);

  products.Reset();
  std_srvs::Trigger request;
  ASSERT_TRUE(ros::service::waitForService("/map_builder/build_map_products", 5000));
  ASSERT_TRUE(ros::service::call("/map_builder/build_map_products", request));
  EXPECT_TRUE(request.response.success) << request.response.message;
  EXPECT_TRUE(products.Wait(180.0)) << "no products after ~build_map_products";
}

TEST(MapBuilderPipeline, ClosesTheLoopOnTheSecondLap) {
  ros::NodeHandle nh;
  ros::NodeHandle pnh("~");
  ReplayOptions options;
  ASSERT_TRUE(pnh.getParam("bag", options.bag_path));
  pnh.param("max_frames", options.max_frames, 0);
  int min_loop_links = 1;
  pnh.param("min_loop_links", min_loop_links, min_loop_links);
  // Lock-step replay: registration needs a reference (1) and waits for the wheel sample after
  // a frame's stamp + 50 ms, which the replay sends only after the next frame's images (2).
  const int delay = 3;

  icgm::ros_bridge::BagReader reader(options.bag_path);
  icgm::ros_bridge::RgbdBagStream stream(reader, icgm::ros_bridge::RgbdBagTopics{});
  const icgm::Trajectory& truth = stream.ground_truth();
  ASSERT_FALSE(truth.empty());

  int odom_count = 0;
  ros::Subscriber odom_sub = nh.subscribe<nav_msgs::Odometry>(
      "/icgm/odom", 200, [&](const nav_msgs::Odometry::ConstPtr&) { ++odom_count; });
  visualization_msgs::MarkerArray::ConstPtr graph;
  ros::Subscriber graph_sub = nh.subscribe<visualization_msgs::MarkerArray>(
      "/icgm/map/graph", 5,
      [&](const visualization_msgs::MarkerArray::ConstPtr& m) { graph = m; });
  tf2_ros::Buffer tf_buffer;
  tf2_ros::TransformListener listener(tf_buffer);

  const int frames =
      ReplayBag(nh, options, [&](int i) { return odom_count >= i + 1 - delay; });
  ASSERT_GE(frames, 100);
  // Let the map builder take the last frames.
  const ros::WallTime end = ros::WallTime::now() + ros::WallDuration(3.0);
  while (ros::WallTime::now() < end) {
    ros::spinOnce();
    ros::WallDuration(0.02).sleep();
  }
  ASSERT_TRUE(graph) << "no graph published";
  size_t nodes = 0, loop_segments = 0;
  for (const auto& m : graph->markers) {
    if (m.ns == "keyframes") nodes = m.points.size();
    if (m.ns == "loop_links") loop_segments = m.points.size() / 2;
  }
  std::printf("map: %zu keyframes, %zu loop links\n", nodes, loop_segments);
  EXPECT_GE(nodes, 10u);
  EXPECT_GE(static_cast<int>(loop_segments), min_loop_links);
  EXPECT_TRUE(tf_buffer.canTransform("map", "odom", ros::Time(0), ros::Duration(1.0)));

  // Save through the service and check every loop link against ground truth.
  const std::string path = (std::filesystem::temp_directory_path() /
                            ("icgm_map_rostest_" + std::to_string(::getpid()) + ".db"))
                               .string();
  icgm_slam::SaveMap save;
  save.request.path = path;
  ASSERT_TRUE(ros::service::waitForService("/map_builder/save_map", 5000));
  ASSERT_TRUE(ros::service::call("/map_builder/save_map", save));
  ASSERT_TRUE(save.response.success) << save.response.message;
  const icgm::HybridMap map = icgm::LoadMap(path);
  std::filesystem::remove(path);
  EXPECT_EQ(static_cast<size_t>(map.size()), nodes);
  CheckMapProductsOnDemand(map);
  // Every loop link and wheel-odometry link against the true relative pose of its keyframes.
  // Wheel links are the wheels' own measurement of each visual step (from /odom and the
  // base -> camera tf): most steps have one.
  int checked = 0, wheel_links = 0;
  for (const icgm::Link& link : map.links()) {
    if (link.type == icgm::LinkType::kOdometry) continue;
    const auto a = icgm::PoseAt(truth, map.keyframe(link.from_id).stamp, 0.2);
    const auto b = icgm::PoseAt(truth, map.keyframe(link.to_id).stamp, 0.2);
    ASSERT_TRUE(a && b);
    const icgm::Pose3 rel = icgm::Between(*a, *b);
    const icgm::Pose3 err = icgm::Between(rel, link.relative_pose);
    if (link.type == icgm::LinkType::kWheelOdometry) {
      EXPECT_LT(icgm::TranslationNorm(err), 0.05 * icgm::TranslationNorm(rel) + 0.02)
          << "wheel link " << link.from_id << "-" << link.to_id;
      EXPECT_LT(icgm::RotationAngleRad(err) * 180 / M_PI, 2.0);
      ++wheel_links;
      continue;
    }
    // A loop link is a constraint: it must agree with the true relative pose of the two
    // keyframes, and they must see the same place.
    std::printf("loop link %d-%d: %.2f m / %.1f deg apart, error %.3f m / %.2f deg\n",
                link.from_id, link.to_id, icgm::TranslationNorm(rel),
                icgm::RotationAngleRad(rel) * 180 / M_PI, icgm::TranslationNorm(err),
                icgm::RotationAngleRad(err) * 180 / M_PI);
    EXPECT_LT(icgm::TranslationNorm(rel), 1.5) << "loop between different places";
    EXPECT_LT(icgm::RotationAngleRad(rel) * 180 / M_PI, 30.0);
    EXPECT_LT(icgm::TranslationNorm(err), 0.15) << "false loop " << link.from_id << "-" << link.to_id;
    EXPECT_LT(icgm::RotationAngleRad(err) * 180 / M_PI, 5.0);
    ++checked;
  }
  EXPECT_EQ(checked, static_cast<int>(loop_segments));
  std::printf("wheel-odometry links: %d\n", wheel_links);
  EXPECT_GT(wheel_links, static_cast<int>(nodes) / 2);
}

}  // namespace
}  // namespace icgm_slam::test
