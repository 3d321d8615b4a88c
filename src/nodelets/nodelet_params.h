// The private parameters the pipeline nodelets share, read one way by all of them: frame
// names, configuration files (a refused file stops the nodelet, naming it), and the camera
// model from camera_info plus the sensor calibration camera_info cannot carry.
#pragma once

#include <functional>
#include <string>

#include <ros/node_handle.h>
#include <sensor_msgs/CameraInfo.h>

#include "core/common/camera.h"
#include "core/common/status.h"

namespace icgm::nodelets {

struct FrameNames {
  std::string map = "map";
  std::string odom = "odom";
  std::string base = "base_link";
};
// ~map_frame, ~odom_frame, ~base_frame (defaults above).
FrameNames ReadFrameNames(const ros::NodeHandle& pnh);

// A parameter's value, `fallback` when it is not set.
template <typename T>
T Param(const ros::NodeHandle& pnh, const std::string& name, const T& fallback) {
  T value = fallback;
  pnh.param(name, value, fallback);
  return value;
}
inline std::string Param(const ros::NodeHandle& pnh, const std::string& name,
                         const char* fallback) {
  return Param<std::string>(pnh, name, fallback);
}

// Runs `load` (reads configuration; throws LoadError). A refused configuration is logged as
// fatal ("<who>: bad configuration: <reason>") and rethrown, so the manager refuses the nodelet.
void LoadConfiguration(const std::string& who, const std::function<void()>& load);

// ~opencv_threads (default 1, as icgm_slam_offline's --threads 1): OpenCV's thread count for
// the whole process (cv::setNumThreads; 0: OpenCV's default, one per core). With 1, the frame
// nodelets compute as the offline front end does, on their own callback thread, without the
// hand-offs to and the spinning of OpenCV's worker threads. The frame nodelets (feature
// extraction, registration) apply it when loaded: give them the same value (icgm_slam.launch's
// opencv_threads).
void ApplyOpenCvThreads(const ros::NodeHandle& pnh, const std::string& who);

// The camera as the core needs it: intrinsics and distortion from camera_info, depth scale
// (~depth_scale, mm per unit of 16-bit depth images, default 1000) and the sensor calibration
// of sensor_calibration.h (~camera_config_file and single parameters; refused values are logged
// and skipped).
class CameraModelReader {
 public:
  CameraModelReader(const ros::NodeHandle& pnh, const std::string& who);
  Status Read(const sensor_msgs::CameraInfo& info, CameraIntrinsics* k) const;
  double depth_scale() const { return depth_scale_; }

 private:
  double depth_scale_ = 1000.0;
  CameraIntrinsics calibration_;
};

}  // namespace icgm::nodelets
