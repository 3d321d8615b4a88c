// Private parameters the nodelets do not know (misspelt in a launch or YAML file) are reported:
// each nodelet, once loaded, warns about every parameter in its private namespace it did not
// read, naming the parameter it probably meant, and says nothing about those it read.
#include <mutex>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <nodelet/NodeletLoad.h>
#include <ros/ros.h>
#include <rosgraph_msgs/Log.h>

namespace icgm_slam::test {
namespace {

class RosoutLog {
 public:
  explicit RosoutLog(ros::NodeHandle& nh)
      : sub_(nh.subscribe<rosgraph_msgs::Log>("/rosout", 200,
                                              [this](const rosgraph_msgs::LogConstPtr& m) {
                                                std::lock_guard<std::mutex> lock(mutex_);
                                                lines_.push_back(m->msg);
                                              })) {}
  // Waits up to `timeout_s` for a line holding `text`.
  bool WaitFor(const std::string& text, double timeout_s) const {
    const ros::WallTime end = ros::WallTime::now() + ros::WallDuration(timeout_s);
    while (ros::WallTime::now() < end) {
      if (Count(text) > 0) return true;
      ros::WallDuration(0.05).sleep();
    }
    return false;
  }
  int Count(const std::string& text) const {
    std::lock_guard<std::mutex> lock(mutex_);
    int n = 0;
    for (const auto& l : lines_) n += l.find(text) != std::string::npos;
    return n;
  }
  std::string All() const {
    std::lock_guard<std::mutex> lock(mutex_);
    std::string all;
    for (const auto& l : lines_) all += l + "\n";
    return all;
  }

 private:
  ros::Subscriber sub_;
  mutable std::mutex mutex_;
  std::vector<std::string> lines_;
};

bool Load(const std::string& name, const std::string& type) {
  nodelet::NodeletLoad srv;
  srv.request.name = name;
  srv.request.type = type;
  return ros::service::call("/params_manager/load_nodelet", srv) && srv.response.success;
}

TEST(NodeletParams, UnknownPrivateParametersAreWarnedWithTheNearestKnownOne) {
  ros::NodeHandle nh;
  RosoutLog log(nh);
  ros::AsyncSpinner spinner(1);
  spinner.start();
  ASSERT_TRUE(ros::service::waitForService("/params_manager/load_nodelet", ros::Duration(30.0)));
  while (log.Count("") == 0 && ros::ok()) {  // our own line through /rosout: subscribed
    ROS_INFO("nodelet params test: waiting for /rosout");
    ros::WallDuration(0.2).sleep();
  }
  // The navigation nodelet: three parameters it reads, one misspelt, one of no nodelet.
  ros::param::set("/nav_typo/map_path", std::string("/nonexistent/map.db"));
  ros::param::set("/nav_typo/pose_wait_s", 1.0);
  ros::param::set("/nav_typo/camera_frame", std::string("camera_rgb_optical_frame"));
  ros::param::set("/nav_typo/contol_rate_hz", 5.0);
  ros::param::set("/nav_typo/colour", std::string("blue"));
  ASSERT_TRUE(Load("/nav_typo", "icgm_slam/navigation"));
  EXPECT_TRUE(log.WaitFor(
      "navigation: unknown parameter ~contol_rate_hz (did you mean ~control_rate_hz?), ignored",
      20.0))
      << log.All();
  EXPECT_TRUE(log.WaitFor("navigation: unknown parameter ~colour, ignored", 5.0)) << log.All();
  // The OpenNI2 driver (no device needed to read its parameters): a misspelt size.
  ros::param::set("/camera_typo/widht_px", 320);
  ros::param::set("/camera_typo/height_px", 240);
  ASSERT_TRUE(Load("/camera_typo", "icgm_slam/openni2_camera"));
  EXPECT_TRUE(log.WaitFor(
      "openni2 camera: unknown parameter ~widht_px (did you mean ~width_px?), ignored", 20.0))
      << log.All();
  // A rate of zero is refused at load, naming the parameter.
  ros::param::set("/nav_zero_rate/map_path", std::string("/nonexistent/map.db"));
  ros::param::set("/nav_zero_rate/control_rate_hz", 0.0);
  EXPECT_FALSE(Load("/nav_zero_rate", "icgm_slam/navigation"));
  EXPECT_TRUE(log.WaitFor("~control_rate_hz 0.000000 not in (0, 1000]", 10.0)) << log.All();
  // Nothing about the parameters they read.
  for (const char* known : {"~map_path", "~pose_wait_s", "~camera_frame", "~height_px"}) {
    EXPECT_EQ(log.Count(std::string("unknown parameter ") + known), 0) << log.All();
  }
}

}  // namespace
}  // namespace icgm_slam::test
