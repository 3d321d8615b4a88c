#include "nodelets/frontend_frame.h"

#include <utility>

#include "ros_bridge/conversions.h"
#include "ros_bridge/feature_msgs.h"

namespace icgm::nodelets {

Status MakeFrontend(const FrontendOptions& options, const Pose3& base_to_camera,
                    const CameraModelReader& camera, const FrontendFrame& frame,
                    KeyframePtr* made_keyframe, CameraIntrinsics* k,
                    std::unique_ptr<RgbdFrontend>* frontend) {
  if (Status s = camera.Read(*frame.info, k); !s) {
    return Status::Error("bad camera_info: " + s.reason());
  }
  FrontendOptions with_extrinsic = options;
  with_extrinsic.fusion.base_to_camera = base_to_camera;
  *frontend = std::make_unique<RgbdFrontend>(with_extrinsic, *k);
  (*frontend)->SetKeyframeCallback(
      [made_keyframe](const KeyframePtr& keyframe) { *made_keyframe = keyframe; });
  return Status::Ok();
}

Status RegisterFrame(const FrontendFrame& frame, double depth_scale, const cv::Mat& bgr,
                     RgbdFrontend* frontend, FrontendFrameResult* result) {
  TrackedFrame features;
  if (Status s = ros_bridge::FromFeaturesMsg(*frame.features, &features); !s) {
    return Status::Error("bad features: " + s.reason());
  }
  cv::Mat depth_m;
  if (Status s = ros_bridge::DepthFromImageMsg(*frame.depth, depth_scale, &depth_m); !s) {
    return Status::Error("bad depth: " + s.reason());
  }
  *result = frontend->ProcessFeatures(features.stamp, std::move(features.features), depth_m,
                                      ros_bridge::FromRos(frame.depth->header.stamp), bgr,
                                      frame.features->keypoints_undistorted);
  return Status::Ok();
}

}  // namespace icgm::nodelets
