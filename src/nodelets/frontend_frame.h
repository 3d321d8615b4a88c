// One synchronised RGB-D frame of the registration nodelet (features + depth + camera_info
// messages) and the core front end it goes through: the front end made for the first frame's
// camera, each frame's messages converted and registered (RgbdFrontend::ProcessFeatures).
#pragma once

#include <memory>

#include <sensor_msgs/CameraInfo.h>
#include <sensor_msgs/Image.h>
#include <opencv2/core.hpp>

#include <icgm_slam/RobustFeatures.h>

#include "core/common/pose.h"
#include "core/common/status.h"
#include "core/odometry/rgbd_frontend.h"
#include "nodelets/nodelet_params.h"

namespace icgm::nodelets {

struct FrontendFrame {
  icgm_slam::RobustFeatures::ConstPtr features;
  sensor_msgs::Image::ConstPtr depth;
  sensor_msgs::CameraInfo::ConstPtr info;
};

// The front end for `frame`'s camera (camera_info through `camera`) with the extrinsic given;
// *made_keyframe receives each keyframe it makes; *k: the camera read. Error: camera_info the
// reader refuses.
Status MakeFrontend(const FrontendOptions& options, const Pose3& base_to_camera,
                    const CameraModelReader& camera, const FrontendFrame& frame,
                    KeyframePtr* made_keyframe, CameraIntrinsics* k,
                    std::unique_ptr<RgbdFrontend>* frontend);

// Registers `frame` (`bgr`: its colour image, or empty); error when a message cannot be
// converted (nothing registered).
Status RegisterFrame(const FrontendFrame& frame, double depth_scale, const cv::Mat& bgr,
                     RgbdFrontend* frontend, FrontendFrameResult* result);

}  // namespace icgm::nodelets
