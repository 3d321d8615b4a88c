// The navigation nodelet's depth input: camera_info gives the intrinsics (CameraModelReader:
// ~depth_scale and the sensor calibration), and each depth image goes to the GoalSession in
// metres with the base -> camera extrinsic and the localized pose of that moment (both from
// NavigationTf). A frame that cannot be used is a reason, never an exception.
#pragma once

#include <cstddef>
#include <string>

#include <ros/node_handle.h>
#include <sensor_msgs/CameraInfo.h>
#include <sensor_msgs/Image.h>

#include "core/common/camera.h"
#include "core/common/status.h"
#include "core/nav/goal_session.h"
#include "nodelets/navigation_tf.h"
#include "nodelets/nodelet_params.h"

namespace icgm::nodelets {

class NavigationDepth {
 public:
  // `nh`: the nodelet's handle its depth and camera_info topics resolve in (for the errors).
  NavigationDepth(const ros::NodeHandle& nh, const ros::NodeHandle& pnh)
      : camera_(pnh, "navigation"),
        depth_topic_(nh.resolveName("depth")),
        info_topic_(nh.resolveName("camera_info")) {}

  void SetInfo(const sensor_msgs::CameraInfo& info) {
    have_info_ = camera_.Read(info, &intrinsics_).ok();
  }
  // Ok when the frame went into the session's obstacle grid; else why not (no extrinsic, no
  // valid camera_info, a bad image, no robot pose on tf, or the session refused it). A depth
  // image of another size than the camera_info is refused (*wrong_size true, counted): its
  // pixels would be back-projected with intrinsics of another image.
  Status Feed(const sensor_msgs::Image& depth, NavigationTf* tf, GoalSession* session,
              bool* wrong_size);

 private:
  CameraModelReader camera_;
  bool have_info_ = false;
  CameraIntrinsics intrinsics_;
  std::string depth_topic_, info_topic_;
  size_t wrong_size_ = 0;  // depth images refused so far
};

}  // namespace icgm::nodelets
