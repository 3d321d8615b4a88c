// Test helper: the colour and registered depth images a camera namespace publishes
// (openni2_launch names), kept by stamp; several images on one stamp stay apart, so a test
// sees a repeated stamp.
#pragma once

#include <map>
#include <mutex>
#include <string>

#include <opencv2/core.hpp>
#include <ros/ros.h>
#include <sensor_msgs/Image.h>

namespace icgm_slam::test {

using ImagesByStamp = std::multimap<ros::Time, sensor_msgs::ImageConstPtr>;

class CameraImages {
 public:
  CameraImages(ros::NodeHandle& nh, const std::string& ns) {
    color_ = nh.subscribe<sensor_msgs::Image>(
        ns + "/rgb/image_color", 100, [this](const sensor_msgs::ImageConstPtr& m) { Add(m, &colors_); });
    depth_ = nh.subscribe<sensor_msgs::Image>(ns + "/depth_registered/image_raw", 100,
                                              [this](const sensor_msgs::ImageConstPtr& m) { Add(m, &depths_); });
  }
  // Both subscriptions reach a publisher (a driver that starts its streams on the first
  // subscriber may otherwise publish its first frames before the other one connects).
  bool connected() const { return color_.getNumPublishers() > 0 && depth_.getNumPublishers() > 0; }
  size_t num_colors() {
    std::lock_guard<std::mutex> lock(mutex_);
    return colors_.size();
  }
  ImagesByStamp colors() {
    std::lock_guard<std::mutex> lock(mutex_);
    return colors_;
  }
  ImagesByStamp depths() {
    std::lock_guard<std::mutex> lock(mutex_);
    return depths_;
  }

 private:
  void Add(const sensor_msgs::ImageConstPtr& m, ImagesByStamp* to) {
    std::lock_guard<std::mutex> lock(mutex_);
    to->emplace(m->header.stamp, m);
  }
  std::mutex mutex_;
  ImagesByStamp colors_, depths_;
  ros::Subscriber color_, depth_;
};

// A bgr8 or 16UC1 image message as a cv::Mat (copied).
inline cv::Mat ImageOf(const sensor_msgs::Image& m) {
  const int type = m.encoding == "bgr8" ? CV_8UC3 : CV_16UC1;
  return cv::Mat(m.height, m.width, type, const_cast<uint8_t*>(m.data.data()), m.step).clone();
}

}  // namespace icgm_slam::test
