#include "nodelets/image_buffer.h"

#include "ros_bridge/conversions.h"

namespace icgm::nodelets {

void ImageBuffer::Add(const sensor_msgs::Image::ConstPtr& image) {
  images_.push_back(image);
  while (images_.size() > capacity_) images_.pop_front();
}

cv::Mat ImageBuffer::Find(const ros::Time& stamp) {
  cv::Mat bgr;
  for (const sensor_msgs::Image::ConstPtr& m : images_) {
    if (m->header.stamp == stamp && ros_bridge::ColorFromImageMsg(*m, &bgr).ok()) return bgr;
  }
  ++missing_;
  return cv::Mat();
}

}  // namespace icgm::nodelets
