#include "bag_replayer.h"

#include <boost/make_shared.hpp>
#include <gtest/gtest.h>
#include <nav_msgs/Odometry.h>
#include <rosbag/bag.h>
#include <rosbag/view.h>
#include <sensor_msgs/CameraInfo.h>
#include <sensor_msgs/Image.h>
#include <tf2_msgs/TFMessage.h>
#include <tf2_ros/static_transform_broadcaster.h>

#include "ros_bridge/conversions.h"
#include "ros_bridge/topics.h"

namespace icgm_slam::test {

namespace topics = icgm::ros_bridge::topics;

bool WaitForSubscribers(const std::vector<ros::Publisher>& pubs, double timeout_s) {
  const ros::WallTime end = ros::WallTime::now() + ros::WallDuration(timeout_s);
  while (ros::ok() && ros::WallTime::now() < end) {
    bool all = true;
    for (const auto& p : pubs) all = all && p.getNumSubscribers() > 0;
    if (all) return true;
    ros::WallDuration(0.05).sleep();
    ros::spinOnce();
  }
  return false;
}

int ReplayBag(ros::NodeHandle& nh, const ReplayOptions& options,
              const std::function<bool(int)>& answered) {
  rosbag::Bag bag(options.bag_path, rosbag::bagmode::Read);
  ros::Publisher rgb_pub = nh.advertise<sensor_msgs::Image>(topics::kRgbImage, 5);
  ros::Publisher depth_pub = nh.advertise<sensor_msgs::Image>(topics::kDepthImageMm, 5);
  ros::Publisher info_pub = nh.advertise<sensor_msgs::CameraInfo>(topics::kRgbInfo, 5);
  ros::Publisher odom_pub = nh.advertise<nav_msgs::Odometry>(topics::kWheelOdom, 50);
  tf2_ros::StaticTransformBroadcaster static_tf;
  EXPECT_TRUE(WaitForSubscribers({rgb_pub, depth_pub, info_pub}, 20.0))
      << "pipeline did not subscribe to the camera topics";
  ros::WallDuration(0.5).sleep();  // let the synchronisers connect

  rosbag::View view(bag, rosbag::TopicQuery({topics::kRgbImage, topics::kDepthImageMm,
                                             topics::kRgbInfo, topics::kWheelOdom,
                                             topics::kTfStatic}));
  // Replay from the bag time of the first_frame-th colour image (messages of one frame share it).
  ros::Time start;
  if (options.first_frame > 0) {
    int seen = 0;
    for (const rosbag::MessageInstance& m : rosbag::View(bag, rosbag::TopicQuery(std::string(topics::kRgbImage)))) {
      if (seen++ == options.first_frame) {
        start = m.getTime() - ros::Duration(0.001);
        break;
      }
    }
  }
  int frame = 0;
  bool rgb_sent = false, depth_sent = false, info_sent = false;
  for (const rosbag::MessageInstance& m : view) {
    if (!ros::ok()) break;
    const std::string& t = m.getTopic();
    if (options.camera_only && (t == topics::kTfStatic || t == topics::kWheelOdom)) continue;
    if (options.no_tf_static && t == topics::kTfStatic) continue;
    if (m.getTime() < start && t != topics::kTfStatic) continue;
    if (t == topics::kTfStatic) {
      if (auto tf = m.instantiate<tf2_msgs::TFMessage>()) static_tf.sendTransform(tf->transforms);
    } else if (t == topics::kWheelOdom) {
      nav_msgs::Odometry::ConstPtr odom = m.instantiate<nav_msgs::Odometry>();
      if (odom && !options.odom_offset.isApprox(icgm::Pose3::Identity())) {
        auto moved = boost::make_shared<nav_msgs::Odometry>(*odom);
        moved->pose.pose = icgm::ros_bridge::ToPoseMsg(
            options.odom_offset * icgm::ros_bridge::FromPoseMsg(odom->pose.pose));
        odom = moved;
      }
      odom_pub.publish(odom);
    } else if (t == topics::kRgbImage) {
      rgb_pub.publish(m.instantiate<sensor_msgs::Image>());
      rgb_sent = true;
    } else if (t == topics::kDepthImageMm) {
      depth_pub.publish(m.instantiate<sensor_msgs::Image>());
      depth_sent = true;
    } else if (t == topics::kRgbInfo) {
      info_pub.publish(m.instantiate<sensor_msgs::CameraInfo>());
      info_sent = true;
    }
    if (rgb_sent && depth_sent && info_sent) {
      rgb_sent = depth_sent = info_sent = false;
      const ros::WallTime end =
          ros::WallTime::now() + ros::WallDuration(options.answer_timeout_s);
      while (ros::ok() && !answered(frame) && ros::WallTime::now() < end) {
        ros::spinOnce();
        ros::WallDuration(0.002).sleep();
      }
      EXPECT_TRUE(answered(frame)) << "no answer for frame " << frame;
      if (!answered(frame)) break;
      ++frame;
      if (options.max_frames > 0 && frame >= options.max_frames) break;
    }
  }
  return frame;
}

}  // namespace icgm_slam::test
