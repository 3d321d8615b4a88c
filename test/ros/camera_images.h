// Test helpers: the colour and registered depth images a camera namespace publishes
// (openni2_launch names), kept by stamp; several images on one stamp stay apart, so a test
// sees a repeated stamp. The spacing a driver's stamps keep on the device clock.
#pragma once

#include <map>
#include <mutex>
#include <string>

#include <gtest/gtest.h>
#include <opencv2/core.hpp>
#include <ros/ros.h>
#include <sensor_msgs/Image.h>

#include "core/sensor/device_clock.h"

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

// Expects the interval between two stamps of a driver (the device clock mapped to ROS time by
// DeviceClock with its default options, as the driver nodelet maps it) to follow the device's
// interval `device_s`: positive, and within what the mapping guarantees whatever the arrivals,
// its slew plus its largest drift. The stamps depend on when frames arrive, so no tighter bound
// holds on a loaded machine (device_clock_test measures the mapping on simulated arrivals).
inline void ExpectDeviceSpacing(const ros::Duration& stamps, double device_s,
                                const std::string& what) {
  const icgm::DeviceClockOptions clock;
  const double bound_s = (clock.max_slew + clock.max_drift_ppm * 1e-6) * device_s + 2e-6;
  EXPECT_GT(stamps.toSec(), 0.0) << what << ": stamps not rising";
  EXPECT_NEAR(stamps.toSec(), device_s, bound_s) << what;
}

}  // namespace icgm_slam::test
