// Images waiting for the camera's lens model: the first valid camera_info fixes the lens
// undistortion (core LensUndistortion) features are extracted with, as offline. Images that
// come before it wait, up to `wait_s` of wall time from the first one (at most `max_waiting`
// of them, the oldest dropped first); after that the undistortion is set to none and the
// features come from the raw image (the consumers then move the keypoints).
#pragma once

#include <cstddef>
#include <deque>
#include <optional>
#include <string>
#include <vector>

#include <ros/time.h>
#include <sensor_msgs/CameraInfo.h>
#include <sensor_msgs/Image.h>

#include "core/common/camera.h"
#include "core/common/status.h"
#include "core/features/lens_undistortion.h"

namespace icgm::nodelets {

class UndistortionGate {
 public:
  explicit UndistortionGate(double wait_s, size_t max_waiting = 30)
      : wait_s_(wait_s), max_waiting_(max_waiting) {}

  // The first valid camera_info fixes the undistortion (later ones are ignored: *fixed false).
  Status SetCameraInfo(const sensor_msgs::CameraInfo& info, bool* fixed);
  // Adds an image; returns the images to process now, in order (empty while waiting). *note:
  // a message for the log ("" when none).
  std::vector<sensor_msgs::Image::ConstPtr> Add(const sensor_msgs::Image::ConstPtr& image,
                                                std::string* note);
  // The images that waited, once the undistortion is fixed.
  std::vector<sensor_msgs::Image::ConstPtr> TakeWaiting();

  // Null until fixed.
  const LensUndistortion* undistortion() const { return undistortion_ ? &*undistortion_ : nullptr; }
  // The camera_info that fixed it (none before, or when fixed as none after the wait).
  const std::optional<CameraIntrinsics>& camera() const { return camera_; }

 private:
  double wait_s_;
  size_t max_waiting_;
  std::optional<LensUndistortion> undistortion_;
  std::optional<CameraIntrinsics> camera_;
  std::deque<sensor_msgs::Image::ConstPtr> waiting_;
  std::optional<ros::WallTime> waiting_since_;
  size_t dropped_ = 0;
};

}  // namespace icgm::nodelets
