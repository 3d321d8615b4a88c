// The simulator nodelet's planar scanner: with the robot at rest and no walkers, every /scan is
// the scan of the same world simulated in process (core/sim/closed_loop_simulator.h) up to the
// range noise, in the scanner's frame; the latched /tf_static, received after the nodelet
// started, holds base -> camera and base -> scanner (one message: a latched topic keeps only
// its last message, so a second one would hide the first).
#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <ros/ros.h>
#include <sensor_msgs/LaserScan.h>
#include <tf2_msgs/TFMessage.h>

#include "core/sim/closed_loop_simulator.h"
#include "core/sim/sim_options.h"
#include "ros_bridge/conversions.h"
#include "ros_bridge/topics.h"

namespace icgm_slam::test {
namespace {

namespace topics = icgm::ros_bridge::topics;

TEST(SimScan, ScansMatchTheWorldAndBothStaticTransformsAreLatched) {
  std::string scenario;
  ASSERT_TRUE(ros::NodeHandle("~").getParam("scenario", scenario));
  icgm::sim::SimOptions options = icgm::sim::LoadSimOptions(scenario);
  options.crowd.num_pedestrians = 0;
  options.scanner.enabled = true;
  const icgm::sim::ClosedLoopSimulator reference(options);
  const icgm::PlanarScan expected = reference.RenderScan();

  ros::NodeHandle nh;
  std::vector<sensor_msgs::LaserScan::ConstPtr> scans;
  std::vector<tf2_msgs::TFMessage::ConstPtr> statics;
  ros::Subscriber scan_sub = nh.subscribe<sensor_msgs::LaserScan>(
      topics::kScan, 50, [&](const sensor_msgs::LaserScan::ConstPtr& m) { scans.push_back(m); });
  ros::Subscriber tf_sub = nh.subscribe<tf2_msgs::TFMessage>(
      topics::kTfStatic, 5,
      [&](const tf2_msgs::TFMessage::ConstPtr& m) { statics.push_back(m); });
  const ros::WallTime end = ros::WallTime::now() + ros::WallDuration(60.0);
  while (ros::ok() && ros::WallTime::now() < end && (scans.size() < 10 || statics.empty())) {
    ros::spinOnce();
    ros::WallDuration(0.02).sleep();
  }
  ASSERT_GE(scans.size(), 10u) << "no /scan from the simulator nodelet";
  ASSERT_EQ(statics.size(), 1u) << "one latched /tf_static message expected";

  // Both transforms, each equal to the simulated mount.
  const auto find = [&](const std::string& child) -> const geometry_msgs::TransformStamped* {
    for (const auto& t : statics.front()->transforms) {
      if (t.child_frame_id == child) return &t;
    }
    return nullptr;
  };
  const auto* camera = find(topics::kCameraFrame);
  const auto* scanner = find(topics::kScannerFrame);
  ASSERT_NE(camera, nullptr) << "base -> camera missing from /tf_static";
  ASSERT_NE(scanner, nullptr) << "base -> scanner missing from /tf_static";
  EXPECT_EQ(camera->header.frame_id, topics::kBaseFrame);
  EXPECT_EQ(scanner->header.frame_id, topics::kBaseFrame);
  const icgm::Pose3 mount = icgm::ros_bridge::FromTransformMsg(scanner->transform);
  EXPECT_LT((mount.translation() - reference.T_base_scanner().translation()).norm(), 1e-6);

  // Every scan: the scanner's frame and geometry, ranges as in the reference within the noise.
  const double noise_m = options.scanner.range_noise_m;
  for (const auto& s : scans) {
    ASSERT_EQ(s->header.frame_id, topics::kScannerFrame);
    ASSERT_EQ(s->ranges.size(), expected.ranges_m.size());
    EXPECT_NEAR(s->angle_min, expected.angle_min_rad, 1e-6);
    EXPECT_NEAR(s->angle_increment, expected.angle_increment_rad, 1e-6);
    std::vector<double> differences;
    size_t returns = 0, agree = 0;
    for (size_t i = 0; i < s->ranges.size(); ++i) {
      const bool got = expected.IsReturn(s->ranges[i]);
      const bool want = expected.IsReturn(expected.ranges_m[i]);
      if (got && want) differences.push_back(std::abs(s->ranges[i] - expected.ranges_m[i]));
      returns += got ? 1 : 0;
      agree += got == want ? 1 : 0;
    }
    // Walls and furniture within range in a good part of the directions, the same beams as in
    // the reference returning (only beams grazing the range limit may differ).
    ASSERT_GT(returns, s->ranges.size() / 4);
    EXPECT_GT(agree, s->ranges.size() * 98 / 100);
    ASSERT_GT(differences.size(), s->ranges.size() / 4);
    std::sort(differences.begin(), differences.end());
    EXPECT_LT(differences[differences.size() / 2], 3.0 * noise_m + 1e-3);
    EXPECT_LT(differences[differences.size() * 95 / 100], 6.0 * noise_m + 0.02);
  }
  std::printf("sim scan: %zu scans of %zu beams, latched /tf_static with %zu transforms\n",
              scans.size(), expected.ranges_m.size(), statics.front()->transforms.size());
}

}  // namespace
}  // namespace icgm_slam::test
