#include "nodelets/odometry_wait.h"

#include <algorithm>
#include <utility>

#include "ros_bridge/conversions.h"

namespace icgm::nodelets {

void OdometryWait::Push(FrontendKeyframe keyframe, const std::string& camera_frame,
                        const ros::Time& stamp) {
  newest_ = std::max(newest_, stamp);
  queue_.push_back({std::move(keyframe), camera_frame, stamp, ros::WallTime::now()});
}

int OdometryWait::Drain(const Ready& ready, std::string* last_error) {
  int dropped = 0;
  while (!queue_.empty()) {
    Held& held = queue_.front();
    geometry_msgs::TransformStamped odom_camera;
    try {
      odom_camera = tf_.lookupTransform(odom_frame_, held.camera_frame, held.stamp);
    } catch (const tf2::TransformException& e) {
      const bool waited = (newest_ - held.stamp).toSec() >= max_wait_s_ &&
                          (ros::WallTime::now() - held.received).toSec() >= max_wait_s_;
      if (!waited) return dropped;
      *last_error = e.what();
      ++dropped;
      queue_.pop_front();
      continue;
    }
    ready(held.keyframe, ros_bridge::FromTransformMsg(odom_camera.transform));
    queue_.pop_front();
  }
  return dropped;
}

}  // namespace icgm::nodelets
