#include "nodelets/navigation_depth.h"

#include <optional>
#include <string>

#include <opencv2/core.hpp>

#include "ros_bridge/conversions.h"
#include "ros_bridge/image_size.h"

namespace icgm::nodelets {

Status NavigationDepth::Feed(const sensor_msgs::Image& depth, NavigationTf* tf,
                             GoalSession* session, bool* wrong_size) {
  *wrong_size = false;
  const std::optional<Pose3> extrinsic = tf->Extrinsic(depth.header.frame_id);
  if (!extrinsic) return Status::Error("no base -> camera extrinsic");
  if (!have_info_) return Status::Error("no valid camera_info");
  if (Status s = ros_bridge::CheckImageSize(depth, depth_topic_, intrinsics_, info_topic_); !s) {
    *wrong_size = true;
    return Status::Error(s.reason() + " (" + std::to_string(++wrong_size_) + " refused so far)");
  }
  cv::Mat depth_m;
  if (Status s = ros_bridge::DepthFromImageMsg(depth, camera_.depth_scale(), &depth_m); !s.ok()) {
    return s;
  }
  std::string pose_error;
  if (!tf->FeedPose(session, &pose_error)) return Status::Error(pose_error);
  return session->UpdateDepth(ros_bridge::FromRos(depth.header.stamp), depth_m, intrinsics_,
                              *extrinsic);
}

}  // namespace icgm::nodelets
