// The private parameters the pipeline nodelets share, read one way by all of them: frame
// names, configuration files (a refused file stops the nodelet, naming it), and the camera
// model from camera_info plus the sensor calibration camera_info cannot carry.
// Every private parameter is read through Param, ParamInto or GetParam, which note its name;
// at the end of onInit each nodelet calls WarnUnknownParams, which warns about every parameter
// in its private namespace that it did not read (a misspelt name in a launch or YAML file would
// otherwise leave the default in force without a word), naming the closest parameter it knows.
#pragma once

#include <functional>
#include <string>
#include <vector>

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

// Records that the nodelet of `pnh` reads the private parameter `name` (done by the readers
// below; call it for a parameter read another way).
void NoteParam(const ros::NodeHandle& pnh, const std::string& name);

// A parameter's value, `fallback` when it is not set.
template <typename T>
T Param(const ros::NodeHandle& pnh, const std::string& name, const T& fallback) {
  NoteParam(pnh, name);
  T value = fallback;
  pnh.param(name, value, fallback);
  return value;
}
// *value = the parameter when set (else unchanged).
template <typename T>
void ParamInto(const ros::NodeHandle& pnh, const std::string& name, T* value) {
  *value = Param(pnh, name, *value);
}
// Whether the parameter is set (and of T's type); its value in *value.
template <typename T>
bool GetParam(const ros::NodeHandle& pnh, const std::string& name, T* value) {
  NoteParam(pnh, name);
  return pnh.getParam(name, *value);
}
inline std::string Param(const ros::NodeHandle& pnh, const std::string& name,
                         const char* fallback) {
  return Param<std::string>(pnh, name, fallback);
}

// The parameters in `pnh`'s namespace (directly in it, not in sub-namespaces) that no reader
// above has noted for it, each as "~name", with " (did you mean ~known?)" when a noted name is
// within two edits, sorted.
std::vector<std::string> UnknownParams(const ros::NodeHandle& pnh);
// Warns "<who>: unknown parameter ~name ..., ignored" for each of UnknownParams(pnh).
void WarnUnknownParams(const ros::NodeHandle& pnh, const std::string& who);

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
