#include "ros_bridge/image_size.h"

#include "core/common/image_size.h"

namespace icgm::ros_bridge {

Status CheckImageSize(const sensor_msgs::Image& image, const std::string& topic,
                      const CameraIntrinsics& k, const std::string& calibration) {
  return icgm::CheckImageSize(k, calibration, static_cast<int>(image.width),
                              static_cast<int>(image.height), "'" + topic + "' carries");
}

Status CheckImageSize(const cv::Mat& image, const std::string& topic, const CameraIntrinsics& k,
                      const std::string& calibration) {
  return icgm::CheckImageSize(k, calibration, image.cols, image.rows, "'" + topic + "' carries");
}

Status CheckImageSize(const sensor_msgs::Image& image, const std::string& topic,
                      const sensor_msgs::CameraInfo& info, const std::string& info_topic) {
  CameraIntrinsics size;
  size.width_px = static_cast<int>(info.width);
  size.height_px = static_cast<int>(info.height);
  return CheckImageSize(image, topic, size, info_topic);
}

}  // namespace icgm::ros_bridge
