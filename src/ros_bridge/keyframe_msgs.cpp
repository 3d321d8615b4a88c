#include "ros_bridge/keyframe_msgs.h"

#include <algorithm>
#include <limits>

#include "core/odometry/odometry_fusion.h"
#include "ros_bridge/conversions.h"
#include "ros_bridge/feature_msgs.h"

namespace icgm::ros_bridge {

icgm_slam::Keyframe ToKeyframeMsg(const FrontendKeyframe& keyframe, const std::string& frame_id,
                                  const sensor_msgs::CameraInfo& camera_info) {
  icgm_slam::Keyframe m;
  m.header.stamp = ToRos(keyframe.stamp);
  m.header.frame_id = frame_id;
  m.id = static_cast<uint32_t>(keyframe.id);
  m.frame_index = static_cast<uint32_t>(keyframe.frame_index);
  m.odom_camera = ToPoseMsg(keyframe.odom_camera);
  m.odom_base = ToPoseMsg(keyframe.odom_base);
  m.relative_pose = ToPoseMsg(keyframe.relative_pose);
  m.relative_source = static_cast<uint8_t>(keyframe.relative_source);
  m.has_covariance = keyframe.covariance.has_value();
  if (keyframe.covariance) {
    for (int r = 0; r < 6; ++r) {
      for (int c = 0; c < 6; ++c) m.covariance[r * 6 + c] = (*keyframe.covariance)(r, c);
    }
  }
  m.has_wheel_camera_motion = keyframe.wheel_camera_motion.has_value();
  if (keyframe.wheel_camera_motion) {
    m.wheel_camera_motion = ToPoseMsg(*keyframe.wheel_camera_motion);
  }
  TrackedFrame frame;
  frame.stamp = keyframe.stamp;
  frame.features = keyframe.features;
  frame.robust = keyframe.robust;
  m.features = ToFeaturesMsg(frame, Time(), frame_id, 0.0);
  m.features.keypoints_undistorted = true;  // the front end's keyframes are on the pinhole image
  m.points_m.reserve(3 * keyframe.points_m.size());
  for (const Eigen::Vector3d& p : keyframe.points_m) {
    m.points_m.insert(m.points_m.end(), {p.x(), p.y(), p.z()});
  }
  if (!keyframe.depth_m.empty()) m.depth = ToImageMsg(keyframe.depth_m, "32FC1", frame_id, keyframe.stamp);
  if (!keyframe.bgr.empty() && keyframe.bgr.type() == CV_8UC3) {
    m.image = ToImageMsg(keyframe.bgr, "bgr8", frame_id, keyframe.stamp);
  }
  m.camera_info = camera_info;
  return m;
}

Status FromKeyframeMsg(const icgm_slam::Keyframe& m, FrontendKeyframe* keyframe) {
  if (m.relative_source > static_cast<uint8_t>(MotionSource::kNone)) {
    return Status::Error("unknown motion source " + std::to_string(m.relative_source));
  }
  TrackedFrame frame;
  if (const Status s = FromFeaturesMsg(m.features, &frame); !s.ok()) return s;
  const size_t n = frame.features.keypoints.size();
  if (m.points_m.size() != 3 * n) {
    return Status::Error("keyframe has " + std::to_string(m.points_m.size()) +
                         " point coordinates for " + std::to_string(n) + " keypoints");
  }
  FrontendKeyframe k;
  k.id = m.id;
  k.frame_index = m.frame_index;
  k.stamp = FromRos(m.header.stamp);
  k.odom_camera = FromPoseMsg(m.odom_camera);
  k.odom_base = FromPoseMsg(m.odom_base);
  k.relative_pose = FromPoseMsg(m.relative_pose);
  k.relative_source = static_cast<MotionSource>(m.relative_source);
  if (m.has_covariance) {
    Mat6 c;
    for (int r = 0; r < 6; ++r) {
      for (int col = 0; col < 6; ++col) c(r, col) = m.covariance[r * 6 + col];
    }
    k.covariance = c;
  }
  if (m.has_wheel_camera_motion) k.wheel_camera_motion = FromPoseMsg(m.wheel_camera_motion);
  k.features = std::move(frame.features);
  k.robust = std::move(frame.robust);
  k.points_m.resize(n);
  for (size_t i = 0; i < n; ++i) {
    k.points_m[i] = Eigen::Vector3d(m.points_m[3 * i], m.points_m[3 * i + 1], m.points_m[3 * i + 2]);
  }
  if (!m.depth.data.empty()) {
    if (const Status s = DepthFromImageMsg(m.depth, 1000.0, &k.depth_m); !s.ok()) return s;
  }
  if (!m.image.data.empty()) {
    if (const Status s = ColorFromImageMsg(m.image, &k.bgr); !s.ok()) return s;
  }
  *keyframe = std::move(k);
  return Status::Ok();
}

}  // namespace icgm::ros_bridge
