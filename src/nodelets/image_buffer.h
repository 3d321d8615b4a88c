// The latest colour images of a camera, found again by stamp: the registration nodelet gets its
// features and depth synchronised, and the colour image (for the motion hypotheses' edge
// evidence) separately. Images are kept as received (no copy, no conversion until asked for).
#pragma once

#include <cstddef>
#include <deque>

#include <opencv2/core.hpp>
#include <ros/time.h>
#include <sensor_msgs/Image.h>

namespace icgm::nodelets {

class ImageBuffer {
 public:
  explicit ImageBuffer(size_t capacity = 100) : capacity_(capacity) {}
  void Add(const sensor_msgs::Image::ConstPtr& image);
  // The BGR image stamped `stamp`; empty (and counted in missing()) when none is held.
  cv::Mat Find(const ros::Time& stamp);
  size_t missing() const { return missing_; }

 private:
  size_t capacity_;
  std::deque<sensor_msgs::Image::ConstPtr> images_;
  size_t missing_ = 0;
};

}  // namespace icgm::nodelets
