#include "nodelets/map_odom_tf.h"

#include <algorithm>

#include "ros_bridge/conversions.h"

namespace icgm::nodelets {

MapOdomTf::MapOdomTf(FrameNames frames, bool camera_only)
    : frames_(std::move(frames)), camera_only_(camera_only), listener_(buffer_) {}

void MapOdomTf::Publish(const SlamSystem& system, const ros::Time& last_stamp) {
  if (last_stamp.isZero()) return;
  if (system.mode() == MapMode::kLocalization && !system.localized()) return;
  geometry_msgs::TransformStamped t;
  t.header.stamp = std::max(last_stamp + ros::Duration(0.1), ros::Time::now());
  if (t.header.stamp <= last_tf_stamp_) return;  // tf2 rejects repeated data
  last_tf_stamp_ = t.header.stamp;
  t.header.frame_id = frames_.map;
  t.child_frame_id = frames_.odom;
  t.transform = ros_bridge::ToTransformMsg(system.MapFromOdom());
  broadcaster_.sendTransform(t);
}

Status MapOdomTf::SetInitialPose(const geometry_msgs::PoseWithCovarianceStamped& msg,
                                 const std::string& camera_frame, SlamSystem* system) const {
  if (!system || camera_frame.empty()) return Status::Error("no keyframe received yet");
  if (msg.header.frame_id != frames_.map) {
    return Status::Error("it is in '" + msg.header.frame_id + "', not '" + frames_.map + "'");
  }
  const auto lookup = [this](const std::string& target, const std::string& source) {
    return ros_bridge::FromTransformMsg(
        buffer_.lookupTransform(target, source, ros::Time(0)).transform);
  };
  Pose3 base_to_camera = Pose3::Identity(), odom_camera;
  try {
    if (!camera_only_) base_to_camera = lookup(frames_.base, camera_frame);
    odom_camera = lookup(frames_.odom, camera_frame);
  } catch (const tf2::TransformException& e) {
    return Status::Error(e.what());
  }
  system->SetInitialPose(ros_bridge::FromPoseMsg(msg.pose.pose) * base_to_camera, odom_camera);
  return Status::Ok();
}

}  // namespace icgm::nodelets
