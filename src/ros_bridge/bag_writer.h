// Writes sensor data into a rosbag (rosbag C++ API, no ROS master needed). Used by the
// simulator and the TUM converter. Topic/frame conventions: see ros_bridge/topics.h.
#pragma once

#include <memory>
#include <string>

#include <opencv2/core.hpp>

#include "core/common/camera.h"
#include "core/common/pose.h"
#include "core/common/time.h"

namespace rosbag {
class Bag;
}

namespace icgm::ros_bridge {

class BagWriter {
 public:
  // Opens `path` for writing (LZ4-compressed chunks). Throws LoadError when it cannot.
  explicit BagWriter(const std::string& path);
  ~BagWriter();
  BagWriter(const BagWriter&) = delete;
  BagWriter& operator=(const BagWriter&) = delete;

  // encoding: bgr8, rgb8, mono8, 16UC1 or 32FC1.
  void WriteImage(const std::string& topic, const std::string& frame_id, Time stamp,
                  const cv::Mat& image, const std::string& encoding);
  void WriteCameraInfo(const std::string& topic, const std::string& frame_id, Time stamp,
                       const CameraIntrinsics& intrinsics);
  void WriteOdometry(const std::string& topic, Time stamp, const std::string& frame_id,
                     const std::string& child_frame_id, const Pose3& pose,
                     const Eigen::Vector3d& linear_velocity_mps,
                     const Eigen::Vector3d& angular_velocity_rps);
  // geometry_msgs/PoseStamped.
  void WritePose(const std::string& topic, Time stamp, const std::string& frame_id,
                 const Pose3& pose);
  // tf2_msgs/TFMessage on /tf, or /tf_static when is_static.
  void WriteTransform(Time stamp, const std::string& parent, const std::string& child,
                      const Pose3& pose, bool is_static);
  // Flushes and closes; the destructor closes too.
  void Close();

 private:
  std::unique_ptr<rosbag::Bag> bag_;
  std::string path_;
};

}  // namespace icgm::ros_bridge
