#include "nodelets/undistortion_gate.h"

#include <cstdio>

#include "ros_bridge/conversions.h"

namespace icgm::nodelets {

Status UndistortionGate::SetCameraInfo(const sensor_msgs::CameraInfo& info, bool* fixed) {
  *fixed = false;
  if (undistortion_) return Status::Ok();
  CameraIntrinsics k;
  if (Status s = ros_bridge::FromCameraInfo(info, 1000.0, &k); !s.ok()) return s;
  undistortion_ = LensUndistortion(k);
  camera_ = k;
  *fixed = true;
  return Status::Ok();
}

std::vector<sensor_msgs::Image::ConstPtr> UndistortionGate::Add(
    const sensor_msgs::Image::ConstPtr& image, std::string* note) {
  note->clear();
  if (!undistortion_) {
    const ros::WallTime now = ros::WallTime::now();
    if (!waiting_since_) waiting_since_ = now;
    if ((now - *waiting_since_).toSec() < wait_s_) {
      waiting_.push_back(image);
      if (waiting_.size() > max_waiting_) {
        waiting_.pop_front();
        *note = "waiting for camera_info; " + std::to_string(++dropped_) + " images dropped so far";
      }
      return {};
    }
    char text[160];
    std::snprintf(text, sizeof(text),
                  "no camera_info after %.1f s: features from the raw image (the consumers move "
                  "the keypoints)",
                  wait_s_);
    *note = text;
    undistortion_.emplace();
  }
  std::vector<sensor_msgs::Image::ConstPtr> ready = TakeWaiting();
  ready.push_back(image);
  return ready;
}

std::vector<sensor_msgs::Image::ConstPtr> UndistortionGate::TakeWaiting() {
  std::vector<sensor_msgs::Image::ConstPtr> out(waiting_.begin(), waiting_.end());
  waiting_.clear();
  return out;
}

}  // namespace icgm::nodelets
