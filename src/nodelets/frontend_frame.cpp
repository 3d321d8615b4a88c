#include "nodelets/frontend_frame.h"

#include <optional>
#include <utility>

#include <ros/console.h>

#include "ros_bridge/conversions.h"
#include "ros_bridge/feature_msgs.h"

namespace icgm::nodelets {

Status ToLiveFrame(const icgm_slam::RobustFeatures& features, const sensor_msgs::Image& depth,
                   double depth_scale, LiveFrame* frame) {
  TrackedFrame tracked;
  if (Status s = ros_bridge::FromFeaturesMsg(features, &tracked); !s) {
    return Status::Error("bad features: " + s.reason());
  }
  if (Status s = ros_bridge::DepthFromImageMsgInto(depth, depth_scale, &frame->depth_m); !s) {
    return Status::Error("bad depth: " + s.reason());
  }
  frame->stamp = tracked.stamp;
  frame->features = std::move(tracked.features);
  frame->keypoints_undistorted = features.keypoints_undistorted;
  frame->depth_stamp = ros_bridge::FromRos(depth.header.stamp);
  frame->camera_frame = features.header.frame_id;
  return Status::Ok();
}

bool StartLiveFrontend(const FrontendOptions& options, ExtrinsicSource* extrinsic,
                       const CameraModelReader& camera, const sensor_msgs::CameraInfo& info,
                       LiveFrontend* live) {
  const LiveFrame* first = live->ReadyFront();
  if (first == nullptr) return false;
  const std::optional<Pose3> base_to_camera = extrinsic->Poll(first->camera_frame);
  if (!base_to_camera) {
    if (extrinsic->expired()) live->Clear();  // nothing to place them with
    return false;
  }
  CameraIntrinsics k;
  if (const Status s = camera.Read(info, &k); !s) {
    ROS_WARN_THROTTLE(5.0, "rgbd registration: bad camera_info: %s", s.reason().c_str());
    live->DropFront();
    return false;
  }
  FrontendOptions with_extrinsic = options;
  with_extrinsic.fusion.base_to_camera = *base_to_camera;
  live->Start(with_extrinsic, k);
  ROS_INFO("rgbd registration: started (extrinsic from %s; %s)", extrinsic->origin(),
           k.HasDistortion() ? "lens distortion from camera_info undone"
                             : "pinhole camera_info, no distortion");
  return true;
}

}  // namespace icgm::nodelets
