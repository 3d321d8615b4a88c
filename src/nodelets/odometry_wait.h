// Keyframes waiting for the fused odometry: the registration nodelet's keyframe arrives before
// the odometry fusion has published tf odom -> camera at its stamp. Each keyframe is held until
// that transform is in the tf buffer; it is given up (and counted) once both its age in
// message time (newest stamp seen minus its stamp) and its wall time in the queue exceed the
// bound, so neither a fast replay nor a loaded machine drops keyframes the odometry will cover.
// Keyframes leave in arrival order.
#pragma once

#include <deque>
#include <functional>
#include <string>

#include <ros/time.h>
#include <tf2_ros/buffer.h>

#include "core/common/pose.h"
#include "core/odometry/frontend_types.h"

namespace icgm::nodelets {

class OdometryWait {
 public:
  // (keyframe, T_odom_camera of the fused odometry at its stamp)
  using Ready = std::function<void(FrontendKeyframe&, const Pose3&)>;

  OdometryWait(const tf2_ros::Buffer& tf, std::string odom_frame, double max_wait_s)
      : tf_(tf), odom_frame_(std::move(odom_frame)), max_wait_s_(max_wait_s) {}

  void Push(FrontendKeyframe keyframe, const std::string& camera_frame, const ros::Time& stamp);
  // Hands every keyframe whose odometry is known to `ready`, in order, and drops those waited
  // for too long (*last_error: why the last one was dropped). Returns how many were dropped.
  int Drain(const Ready& ready, std::string* last_error);
  size_t size() const { return queue_.size(); }

 private:
  struct Held {
    FrontendKeyframe keyframe;
    std::string camera_frame;
    ros::Time stamp;
    ros::WallTime received;
  };
  const tf2_ros::Buffer& tf_;
  std::string odom_frame_;
  double max_wait_s_;
  std::deque<Held> queue_;
  ros::Time newest_;
};

}  // namespace icgm::nodelets
