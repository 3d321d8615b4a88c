// The mono_odometry nodelet replays a bag's colour images (camera_info first; with ~wheels also
// the wheel odometry and /tf_static, in bag order) and must give the trajectory
// icgm_mono_vo --bag gives on the same bag (the same core on the same frames: equal within
// ~max_difference_units, map units), with the scale flagged unknown (no wheels) or metric
// (wheels) in every message, tf odom_frame -> child_frame published, and a Sim(3) ATE against
// the bag's ground truth below ~max_ate_m.
// The replay stays at most ~10 images ahead of the nodelet's answers, so no frame or wheel
// sample is dropped from a subscriber queue whatever the machine's load.
// ~refused_images (default 0): that many of the bag's images are also sent at half size, 1 ms
// before their original, against the bag's full-size camera_info: the nodelet must refuse them
// (no pose at their stamps) and still give the tool's trajectory for the others.
#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <map>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <nav_msgs/Odometry.h>
#include <opencv2/imgproc.hpp>
#include <ros/ros.h>
#include <rosbag/bag.h>
#include <rosbag/view.h>
#include <sensor_msgs/CameraInfo.h>
#include <sensor_msgs/Image.h>
#include <tf2_msgs/TFMessage.h>

#include "core/dataset/trajectory.h"
#include "core/mono/mono_evaluation.h"
#include "ros_bridge/bag_reader.h"
#include "ros_bridge/conversions.h"
#include "sibling_executable.h"
#include "ros_bridge/mono_msgs.h"
#include "ros_bridge/topics.h"

namespace icgm_slam::test {
namespace {

namespace topics = icgm::ros_bridge::topics;

TEST(MonoOdometryNodelet, MatchesTheOfflineToolAndTheGroundTruth) {
  ros::NodeHandle nh;
  ros::NodeHandle pnh("~");
  std::string bag_path, tool, config_file;
  ASSERT_TRUE(pnh.getParam("bag", bag_path));
  pnh.param<std::string>("mono_vo", tool, "");
  if (tool.empty()) tool = SiblingExecutable("icgm_mono_vo");
  ASSERT_TRUE(pnh.getParam("config_file", config_file));
  double max_difference_units = 1e-4, max_ate_m = 0.02;
  pnh.param("max_difference_units", max_difference_units, max_difference_units);
  pnh.param("max_ate_m", max_ate_m, max_ate_m);
  bool wheels = false;
  pnh.param("wheels", wheels, wheels);
  int refused_images = 0;
  pnh.param("refused_images", refused_images, refused_images);

  // 1. Offline: the tool on the bag (before the replay: the two never share the CPU).
  const std::string out = "/tmp/icgm_mono_rostest_" + std::to_string(getpid()) + ".txt";
  const std::string cmd = tool + " --bag " + bag_path + " --config " + config_file +
                          (wheels ? "" : " --no-wheels") +
                          " --output " + out + " > " + out + ".log 2>&1";
  ASSERT_EQ(std::system(cmd.c_str()), 0) << cmd;
  const icgm::Trajectory offline = icgm::ReadTumTrajectory(out);
  std::remove(out.c_str());
  std::remove((out + ".log").c_str());
  ASSERT_GE(offline.size(), 50u) << "the tool tracked too few frames";

  icgm::ros_bridge::BagReader reader(bag_path);
  icgm::ros_bridge::RgbdBagStream stream(reader, icgm::ros_bridge::RgbdBagTopics{});
  ASSERT_FALSE(stream.ground_truth().empty()) << bag_path << " has no ground truth";

  // 2. Live: camera_info (latched) and every colour image of the bag.
  std::vector<nav_msgs::Odometry::ConstPtr> odom;
  ros::Subscriber odom_sub = nh.subscribe<nav_msgs::Odometry>(
      "/icgm/mono_odom", 1000, [&](const nav_msgs::Odometry::ConstPtr& m) { odom.push_back(m); });
  size_t tf_seen = 0;
  std::string tf_parent, tf_child;
  ros::Subscriber tf_sub = nh.subscribe<tf2_msgs::TFMessage>(
      topics::kTf, 1000, [&](const tf2_msgs::TFMessage::ConstPtr& m) {
        for (const auto& t : m->transforms) {
          ++tf_seen;
          tf_parent = t.header.frame_id;
          tf_child = t.child_frame_id;
        }
      });
  ros::Publisher rgb_pub = nh.advertise<sensor_msgs::Image>(topics::kRgbImage, 1000);
  ros::Publisher info_pub = nh.advertise<sensor_msgs::CameraInfo>(topics::kRgbInfo, 1, true);
  ros::Publisher wheel_pub = nh.advertise<nav_msgs::Odometry>(topics::kWheelOdom, 5000);
  ros::Publisher static_pub = nh.advertise<tf2_msgs::TFMessage>(topics::kTfStatic, 10, true);
  const ros::WallTime wait_end = ros::WallTime::now() + ros::WallDuration(30.0);
  while (ros::ok() && ros::WallTime::now() < wait_end &&
         (rgb_pub.getNumSubscribers() == 0 || info_pub.getNumSubscribers() == 0 ||
          odom_sub.getNumPublishers() == 0 || (wheels && wheel_pub.getNumSubscribers() == 0))) {
    ros::WallDuration(0.05).sleep();
  }
  ASSERT_GT(rgb_pub.getNumSubscribers(), 0u) << "the nodelet did not subscribe";
  ros::WallDuration(0.5).sleep();

  rosbag::Bag bag(bag_path, rosbag::bagmode::Read);
  bool info_sent = false;
  int images = 0, half_size = 0;
  for (const rosbag::MessageInstance& m :
       rosbag::View(bag, rosbag::TopicQuery(std::vector<std::string>{
                             topics::kRgbImage, topics::kRgbInfo, topics::kWheelOdom,
                             topics::kTfStatic}))) {
    if (!ros::ok()) break;
    if (m.getTopic() == topics::kTfStatic) {
      if (wheels) static_pub.publish(m.instantiate<tf2_msgs::TFMessage>());
    } else if (m.getTopic() == topics::kWheelOdom) {
      if (wheels) wheel_pub.publish(m.instantiate<nav_msgs::Odometry>());
    } else if (m.getTopic() == topics::kRgbInfo && !info_sent) {
      info_pub.publish(m.instantiate<sensor_msgs::CameraInfo>());
      info_sent = true;
    } else if (m.getTopic() == topics::kRgbImage) {
      ASSERT_TRUE(info_sent) << "an image before the first camera_info";
      const sensor_msgs::Image::ConstPtr image = m.instantiate<sensor_msgs::Image>();
      if (images % 10 == 5 && half_size < refused_images) {
        cv::Mat bgr, half;
        ASSERT_TRUE(icgm::ros_bridge::ColorFromImageMsg(*image, &bgr).ok());
        cv::resize(bgr, half, cv::Size(bgr.cols / 2, bgr.rows / 2), 0, 0, cv::INTER_AREA);
        rgb_pub.publish(icgm::ros_bridge::ToImageMsg(
            half, "bgr8", image->header.frame_id,
            icgm::ros_bridge::FromRos(image->header.stamp - ros::Duration(0.001))));
        ++half_size;
      }
      rgb_pub.publish(image);
      ++images;
      // At most ~10 images ahead of the answers (a few frames have no pose; bounded wait),
      // so no subscriber queue overflows while the nodelet works.
      const ros::WallTime give_up = ros::WallTime::now() + ros::WallDuration(5.0);
      do {
        ros::spinOnce();
        ros::WallDuration(0.005).sleep();
      } while (ros::ok() && ros::WallTime::now() < give_up &&
               images - static_cast<int>(odom.size()) > 10);
    }
  }
  ASSERT_GE(images, 50);
  ASSERT_EQ(half_size, refused_images);
  // Until the pose of the offline run's last frame arrives, or nothing arrives for 30 s.
  const ros::Time last = icgm::ros_bridge::ToRos(offline.back().stamp);
  ros::WallTime quiet_end = ros::WallTime::now() + ros::WallDuration(30.0);
  size_t seen = 0;
  while (ros::ok() && ros::WallTime::now() < quiet_end &&
         (odom.empty() || odom.back()->header.stamp < last)) {
    ros::spinOnce();
    ros::WallDuration(0.01).sleep();
    if (odom.size() != seen) {
      seen = odom.size();
      quiet_end = ros::WallTime::now() + ros::WallDuration(30.0);
    }
  }
  ros::WallDuration(0.3).sleep();
  ros::spinOnce();
  ASSERT_FALSE(odom.empty()) << "no odometry from the nodelet";

  // 3. Same core, same frames: the same poses. The tool also lists the pose it gives the
  // initialization's reference frame, which the nodelet does not publish afterwards.
  std::map<int64_t, icgm::Pose3> offline_at;
  for (const auto& p : offline) offline_at[p.stamp.nanoseconds()] = p.pose;
  icgm::Trajectory live;
  double max_difference = 0.0;
  size_t unmatched = 0;
  for (const auto& m : odom) {
    EXPECT_EQ(m->header.frame_id, "mono_odom");
    EXPECT_EQ(m->child_frame_id, "mono_camera");
    if (!wheels) {
      EXPECT_FALSE(icgm::ros_bridge::MonoScaleKnown(*m)) << "no wheels: the scale is unknown";
    }
    const icgm::Time stamp = icgm::ros_bridge::FromRos(m->header.stamp);
    const icgm::Pose3 pose = icgm::ros_bridge::FromPoseMsg(m->pose.pose);
    live.push_back({stamp, pose});
    const auto it = offline_at.find(stamp.nanoseconds());
    if (it == offline_at.end()) {
      ++unmatched;
      continue;
    }
    max_difference =
        std::max(max_difference, (it->second.translation() - pose.translation()).norm());
  }
  std::printf("nodelet: %zu poses of %d images; tool: %zu poses; largest position difference "
              "%.3g map units\n", odom.size(), images, offline.size(), max_difference);
  EXPECT_EQ(unmatched, 0u) << "poses at stamps the tool has no pose for (" << half_size
                           << " half-size images sent, to be refused)";
  if (wheels) {
    EXPECT_TRUE(icgm::ros_bridge::MonoScaleKnown(*odom.back())) << "wheels: metric";
  }
  EXPECT_GE(odom.size() + 1, offline.size()) << "the nodelet tracked fewer frames than the tool";
  EXPECT_LE(max_difference, max_difference_units);
  EXPECT_GT(tf_seen, 0u);
  EXPECT_EQ(tf_parent, "mono_odom");
  EXPECT_EQ(tf_child, "mono_camera");

  // 4. Against the ground truth, one Sim(3) over the run.
  icgm::MonoEvaluation eval;
  const icgm::Status s = icgm::EvaluateMonoTrajectory(stream.ground_truth(), live, 0.02, &eval);
  ASSERT_TRUE(s.ok()) << s.reason();
  std::printf("nodelet Sim(3) ATE %.4f m over %zu poses (%.2f %% of %.2f m)\n",
              eval.evaluation.ate.rmse, eval.evaluation.num_associated(), eval.error_percent,
              eval.distance_m);
  EXPECT_LE(eval.evaluation.ate.rmse, max_ate_m);
}

}  // namespace
}  // namespace icgm_slam::test
