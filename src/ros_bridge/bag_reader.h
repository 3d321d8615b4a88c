// Reads recorded sensor data from a rosbag without a ROS master (rosbag C++ API):
// BagReader lists what a bag holds; RgbdBagStream streams synchronised RGB-D frames with the
// camera intrinsics, the static camera extrinsic, wheel odometry and ground truth.
// A missing or corrupt bag, or a missing topic, is a LoadError with a clear message; corruption
// in the middle of a bag ends the stream with a Status reason, keeping every frame before it.
#pragma once

#include <deque>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <opencv2/core.hpp>

#include "core/common/camera.h"
#include "core/common/pose.h"
#include "core/common/status.h"
#include "core/common/time.h"
#include "core/dataset/trajectory.h"

namespace rosbag {
class Bag;
class View;
}  // namespace rosbag

namespace icgm::ros_bridge {

struct TopicInfo {
  std::string name;
  std::string datatype;
  size_t message_count = 0;
  Time first_stamp;
  Time last_stamp;
};

class BagReader {
 public:
  // Throws LoadError when the file is missing, not a bag, truncated or unindexed.
  explicit BagReader(const std::string& path);
  ~BagReader();
  BagReader(const BagReader&) = delete;
  BagReader& operator=(const BagReader&) = delete;

  const std::string& path() const { return path_; }
  // Topics sorted by name, with message counts and first/last receive stamps.
  const std::vector<TopicInfo>& Topics() const { return topics_; }
  const TopicInfo* FindTopic(const std::string& name) const;
  rosbag::Bag& bag() const { return *bag_; }

 private:
  std::unique_ptr<rosbag::Bag> bag_;
  std::string path_;
  std::vector<TopicInfo> topics_;
};

struct RgbdBagTopics {
  std::string rgb = "/camera/rgb/image_color";
  // Empty: /camera/depth_registered/image_raw (16UC1 mm) if present, else .../image (32FC1 m).
  std::string depth;
  std::string camera_info = "/camera/rgb/camera_info";
  std::string wheel_odometry = "/odom";
  std::string ground_truth = "/ground_truth/pose";
  std::string dynamic_mask = "/ground_truth/dynamic_mask";
  double max_sync_dt_s = 0.02;   // RGB/depth stamps further apart are not paired
  double depth_scale_16u = 1000.0;  // 16UC1 units per metre
  // Used when the bag has no camera_info; without it a missing camera_info is an error.
  std::optional<CameraIntrinsics> fallback_intrinsics;
};

struct RgbdBagFrame {
  Time stamp;            // RGB stamp
  Time depth_stamp;      // stamp of the paired depth image
  cv::Mat bgr;           // CV_8UC3
  cv::Mat depth_m;       // CV_32FC1, NaN invalid
  cv::Mat dynamic_mask;  // CV_8UC1 if the bag has ground-truth masks, else empty
};

class RgbdBagStream {
 public:
  // Reads camera_info, /tf_static, wheel odometry and ground truth up front (small messages),
  // then streams frames. Throws LoadError when the RGB or depth topic or the intrinsics are
  // missing.
  RgbdBagStream(const BagReader& reader, const RgbdBagTopics& topics);
  ~RgbdBagStream();

  const CameraIntrinsics& intrinsics() const { return intrinsics_; }
  // base_link -> camera optical frame from /tf_static, when the bag has it.
  const std::optional<Pose3>& base_to_camera() const { return base_to_camera_; }
  const Trajectory& wheel_odometry() const { return wheel_odometry_; }  // odom -> base_link
  const Trajectory& ground_truth() const { return ground_truth_; }      // camera in world
  size_t expected_frames() const { return expected_frames_; }
  const std::string& depth_topic() const { return topics_.depth; }

  // Next synchronised frame in time order; false at the end of the bag or on corruption
  // (then status() says why).
  bool Next(RgbdBagFrame* frame);
  const Status& status() const { return status_; }
  // Messages dropped, by reason ("unpaired rgb", "time went backwards", "bad encoding: ...").
  const std::map<std::string, size_t>& dropped() const { return dropped_; }

 private:
  struct Pending;
  void Drop(const std::string& reason) { ++dropped_[reason]; }
  bool Emit(RgbdBagFrame* frame);

  RgbdBagTopics topics_;
  CameraIntrinsics intrinsics_;
  std::optional<Pose3> base_to_camera_;
  Trajectory wheel_odometry_;
  Trajectory ground_truth_;
  size_t expected_frames_ = 0;
  std::unique_ptr<rosbag::View> view_;
  std::unique_ptr<Pending> pending_;
  Status status_ = Status::Ok();
  std::map<std::string, size_t> dropped_;
  std::optional<Time> last_emitted_;
};

}  // namespace icgm::ros_bridge
