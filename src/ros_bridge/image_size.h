// Images meet the intrinsics they are combined with (camera_info or a camera YAML): one size
// check for every nodelet that back-projects an image's pixels (core/common/image_size.h).
#pragma once

#include <string>

#include <opencv2/core.hpp>
#include <sensor_msgs/CameraInfo.h>
#include <sensor_msgs/Image.h>

#include "core/common/camera.h"
#include "core/common/status.h"

namespace icgm::ros_bridge {

// Whether `image` (received on `topic`) has the size `k` was calibrated for (`calibration`: the
// camera_info topic or camera YAML it came from). The error names both sizes and the topic.
Status CheckImageSize(const sensor_msgs::Image& image, const std::string& topic,
                      const CameraIntrinsics& k, const std::string& calibration);
// The same for an image already converted from a message of `topic` (e.g. one that waited for
// the camera_info).
Status CheckImageSize(const cv::Mat& image, const std::string& topic, const CameraIntrinsics& k,
                      const std::string& calibration);
// The same against a camera_info message's size (before it is converted), e.g. a depth image
// against the colour camera's camera_info: depth not registered to colour has another size.
Status CheckImageSize(const sensor_msgs::Image& image, const std::string& topic,
                      const sensor_msgs::CameraInfo& info, const std::string& info_topic);

}  // namespace icgm::ros_bridge
