#include "nodelets/extrinsic_source.h"

#include <ros/console.h>

#include "nodelets/nodelet_params.h"
#include "ros_bridge/conversions.h"

namespace icgm::nodelets {

ExtrinsicSource::ExtrinsicSource(const ros::NodeHandle& pnh, std::string base_frame,
                                 const Pose3& configured, std::string who)
    : base_frame_(std::move(base_frame)), configured_(configured), who_(std::move(who)) {
  camera_only_ = Param(pnh, "camera_only", false);
  from_config_ = Param(pnh, "extrinsic_from_config", false);
  wait_s_ = Param(pnh, "extrinsic_wait_s", 5.0);
  if (camera_only_ && from_config_) {
    ROS_WARN("%s: ~camera_only and ~extrinsic_from_config both set; camera only wins",
             who_.c_str());
  }
  if (camera_only_) {
    known_ = Pose3::Identity();
  } else if (from_config_) {
    known_ = configured_;
  } else {
    buffer_ = std::make_unique<tf2_ros::Buffer>();
    listener_ = std::make_unique<tf2_ros::TransformListener>(*buffer_);
  }
}

const char* ExtrinsicSource::origin() const {
  return camera_only_ ? "camera only" : from_config_ ? "config" : "tf";
}

std::optional<Pose3> ExtrinsicSource::Poll(const std::string& camera_frame) {
  if (known_) return known_;
  const ros::WallTime now = ros::WallTime::now();
  if (!first_poll_) first_poll_ = now;
  std::string why;
  try {
    const auto t = buffer_->lookupTransform(base_frame_, camera_frame, ros::Time(0));
    known_ = ros_bridge::FromTransformMsg(t.transform);
    listener_.reset();  // static: no need to keep listening to /tf
    ROS_INFO("%s: extrinsic %s -> %s from tf after %.1f s", who_.c_str(), base_frame_.c_str(),
             camera_frame.c_str(), (now - *first_poll_).toSec());
    return known_;
  } catch (const tf2::TransformException& e) {
    why = e.what();
  }
  const double waited_s = (now - *first_poll_).toSec();
  if (waited_s < wait_s_) {
    ROS_INFO_THROTTLE(1.0, "%s: waiting for tf %s -> %s (%.1f of %.1f s): input held", who_.c_str(),
                      base_frame_.c_str(), camera_frame.c_str(), waited_s, wait_s_);
  } else {
    ROS_ERROR_THROTTLE(5.0,
                       "%s: no tf %s -> %s after %.1f s (%s); input dropped until it arrives. "
                       "Publish it on /tf_static, or set ~extrinsic_from_config (the config's "
                       "fusion.base_to_camera_*) or ~camera_only (no wheels)",
                       who_.c_str(), base_frame_.c_str(), camera_frame.c_str(), waited_s,
                       why.c_str());
  }
  return std::nullopt;
}

}  // namespace icgm::nodelets
