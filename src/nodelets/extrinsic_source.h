// Where a nodelet takes the static base -> camera extrinsic from, and the bounded wait for it.
//
// "Wait, don't guess": by default the extrinsic comes from tf (base_frame -> the camera's
// optical frame, normally /tf_static). A nodelet that starts before the transform is known keeps
// its input pending and polls, logging a throttled status; after ~extrinsic_wait_s (wall time
// from the first poll) it reports an error, still without assuming identity, and keeps polling.
// The alternatives are explicit:
//   ~camera_only: true           hand-held camera without wheels: the camera is the base
//                                (identity extrinsic, odometry child frame = the camera frame)
//   ~extrinsic_from_config: true fusion.base_to_camera_* of the nodelet's config file
#pragma once

#include <memory>
#include <optional>
#include <string>

#include <ros/node_handle.h>
#include <ros/time.h>
#include <tf2_ros/buffer.h>
#include <tf2_ros/transform_listener.h>

#include "core/common/pose.h"

namespace icgm::nodelets {

class ExtrinsicSource {
 public:
  // Reads ~camera_only, ~extrinsic_from_config and ~extrinsic_wait_s (default 5) from `pnh`.
  // `configured`: the config file's extrinsic; `who`: the nodelet's name for messages.
  ExtrinsicSource(const ros::NodeHandle& pnh, std::string base_frame, const Pose3& configured,
                  std::string who);

  // Non-blocking: the extrinsic T_base_camera when known. Otherwise nullopt, with a throttled
  // status while waiting and a throttled error once the wait bound has passed.
  std::optional<Pose3> Poll(const std::string& camera_frame);

  // The wait bound has passed without the transform (callers stop holding input).
  bool expired() const {
    return !known_ && first_poll_ && (ros::WallTime::now() - *first_poll_).toSec() >= wait_s_;
  }
  bool camera_only() const { return camera_only_; }
  // The odometry's child frame: the base frame, or the camera frame in camera-only mode.
  std::string BaseFrame(const std::string& camera_frame) const {
    return camera_only_ ? camera_frame : base_frame_;
  }
  const std::string& base_frame() const { return base_frame_; }
  // Where the extrinsic came from ("tf", "config", "camera only"), for log lines.
  const char* origin() const;

 private:
  std::string base_frame_;
  Pose3 configured_;
  std::string who_;
  bool camera_only_ = false;
  bool from_config_ = false;
  double wait_s_ = 5.0;
  std::optional<ros::WallTime> first_poll_;
  std::optional<Pose3> known_;
  std::unique_ptr<tf2_ros::Buffer> buffer_;
  std::unique_ptr<tf2_ros::TransformListener> listener_;
};

}  // namespace icgm::nodelets
