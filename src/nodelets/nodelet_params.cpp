#include "nodelets/nodelet_params.h"

#include <opencv2/core/utility.hpp>
#include <ros/console.h>

#include "core/common/option_reader.h"
#include "core/dataset/camera_options.h"
#include "nodelets/sensor_calibration.h"
#include "ros_bridge/conversions.h"

namespace icgm::nodelets {

FrameNames ReadFrameNames(const ros::NodeHandle& pnh) {
  FrameNames f;
  f.map = Param(pnh, "map_frame", f.map);
  f.odom = Param(pnh, "odom_frame", f.odom);
  f.base = Param(pnh, "base_frame", f.base);
  return f;
}

void LoadConfiguration(const std::string& who, const std::function<void()>& load) {
  try {
    load();
  } catch (const LoadError& e) {
    ROS_FATAL("%s: bad configuration: %s", who.c_str(), e.what());
    throw;
  }
}

void ApplyOpenCvThreads(const ros::NodeHandle& pnh, const std::string& who) {
  const int threads = Param(pnh, "opencv_threads", 1);
  if (threads < 0) {
    ROS_ERROR("%s: ~opencv_threads %d < 0: OpenCV's thread count left as it is", who.c_str(),
              threads);
    return;
  }
  cv::setNumThreads(threads > 0 ? threads : -1);  // -1: OpenCV's default
}

CameraModelReader::CameraModelReader(const ros::NodeHandle& pnh, const std::string& who)
    : depth_scale_(Param(pnh, "depth_scale", 1000.0)) {
  std::string error;
  calibration_ = ReadSensorCalibration(pnh, &error);
  if (!error.empty()) ROS_ERROR("%s: %s (ignored)", who.c_str(), error.c_str());
}

Status CameraModelReader::Read(const sensor_msgs::CameraInfo& info, CameraIntrinsics* k) const {
  if (Status s = ros_bridge::FromCameraInfo(info, depth_scale_, k); !s.ok()) return s;
  CopySensorCalibration(calibration_, k);
  return Status::Ok();
}

}  // namespace icgm::nodelets
