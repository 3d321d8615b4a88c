// A hand-held camera (no wheels, no base link, no /tf_static) through the whole pipeline with
// camera_only:=true: the fused odometry's child frame is the camera frame, and the map builder
// maps (keyframes on the published path) instead of skipping every frame for want of a
// base -> camera transform.
#include <cstdio>
#include <optional>

#include <gtest/gtest.h>
#include <nav_msgs/Odometry.h>
#include <nav_msgs/Path.h>

#include "bag_replayer.h"
#include "ros_bridge/bag_reader.h"
#include "ros_bridge/conversions.h"
#include "ros_bridge/topics.h"

namespace icgm_slam::test {
namespace {

TEST(CameraOnlyPipeline, MapsAndPublishesThePathWithoutWheelsOrExtrinsic) {
  ros::NodeHandle nh;
  ros::NodeHandle pnh("~");
  ReplayOptions options;
  ASSERT_TRUE(pnh.getParam("bag", options.bag_path));
  pnh.param("max_frames", options.max_frames, 60);
  options.camera_only = true;
  const int delay = 1;  // registration needs a reference (features come without delay)

  icgm::ros_bridge::BagReader reader(options.bag_path);
  icgm::ros_bridge::RgbdBagStream stream(reader, icgm::ros_bridge::RgbdBagTopics{});
  ASSERT_FALSE(stream.ground_truth().empty());

  std::vector<nav_msgs::Odometry::ConstPtr> odom;
  ros::Subscriber odom_sub = nh.subscribe<nav_msgs::Odometry>(
      "/icgm/odom", 200, [&](const nav_msgs::Odometry::ConstPtr& m) { odom.push_back(m); });
  nav_msgs::Path::ConstPtr path;
  ros::Subscriber path_sub = nh.subscribe<nav_msgs::Path>(
      "/icgm/map/path", 5, [&](const nav_msgs::Path::ConstPtr& m) { path = m; });

  const int frames =
      ReplayBag(nh, options, [&](int i) { return static_cast<int>(odom.size()) >= i + 1 - delay; });
  ASSERT_GE(frames, 40);
  EXPECT_EQ(static_cast<int>(odom.size()), frames - delay);
  const ros::WallTime end = ros::WallTime::now() + ros::WallDuration(3.0);
  while (ros::WallTime::now() < end) {
    ros::spinOnce();
    ros::WallDuration(0.02).sleep();
  }
  ASSERT_FALSE(odom.empty());
  EXPECT_EQ(odom.back()->child_frame_id, icgm::ros_bridge::topics::kCameraFrame);

  // The odometry is the camera's own pose: it follows the ground truth's motion.
  std::optional<icgm::Pose3> est0, gt0;
  double sq = 0, travelled = 0;
  for (const auto& m : odom) {
    const auto truth =
        icgm::PoseAt(stream.ground_truth(), icgm::ros_bridge::FromRos(m->header.stamp), 0.01);
    ASSERT_TRUE(truth.has_value());
    const icgm::Pose3 camera = icgm::ros_bridge::FromPoseMsg(m->pose.pose);
    if (!est0) {
      est0 = camera;
      gt0 = *truth;
    }
    const icgm::Pose3 gt_rel = icgm::Between(*gt0, *truth);
    const double err =
        (icgm::Between(*est0, camera).translation() - gt_rel.translation()).norm();
    sq += err * err;
    travelled = std::max(travelled, gt_rel.translation().norm());
  }
  const double rmse = std::sqrt(sq / odom.size());
  std::printf("camera only: %zu poses, %.2f m from the start, drift RMSE %.4f m; path %zu poses\n",
              odom.size(), travelled, rmse, path ? path->poses.size() : 0u);
  EXPECT_GT(travelled, 0.5);
  EXPECT_LT(rmse, 0.05 * travelled);

  // The map builder mapped: keyframes on the path.
  ASSERT_TRUE(path) << "no map path published";
  EXPECT_GE(path->poses.size(), 3u);
}

}  // namespace
}  // namespace icgm_slam::test
