#include "nodelets/navigation_tf.h"

#include <cmath>

#include <tf2_geometry_msgs/tf2_geometry_msgs.h>

#include "ros_bridge/conversions.h"

namespace icgm::nodelets {

NavigationTf::NavigationTf(const ros::NodeHandle& pnh, std::string map_frame,
                           std::string odom_frame, std::string base_frame)
    : map_frame_(std::move(map_frame)),
      odom_frame_(std::move(odom_frame)),
      base_frame_(std::move(base_frame)),
      listener_(buffer_),
      extrinsic_(pnh, base_frame_, Pose3::Identity(), "navigation"),
      scanner_extrinsic_(pnh, base_frame_, Pose3::Identity(), "navigation scan") {}

Status NavigationTf::LocalizedBase(Pose3* T_map_base, Time* stamp, bool* fix) {
  try {
    const auto base = buffer_.lookupTransform(map_frame_, base_frame_, ros::Time(0));
    const Pose3 map_odom = ros_bridge::FromTransformMsg(
        buffer_.lookupTransform(map_frame_, odom_frame_, ros::Time(0)).transform);
    *fix = !last_map_odom_ || !last_map_odom_->isApprox(map_odom, 1e-9);
    last_map_odom_ = map_odom;
    *T_map_base = ros_bridge::FromTransformMsg(base.transform);
    // A chain of static transforms holds at any time: stamped now.
    *stamp = ros_bridge::FromRos(base.header.stamp.isZero() ? ros::Time::now() : base.header.stamp);
    return Status::Ok();
  } catch (const tf2::TransformException& e) {
    return Status::Error("no robot pose (tf " + map_frame_ + " -> " + base_frame_ +
                         "): " + e.what());
  }
}

Status NavigationTf::GoalInMap(const geometry_msgs::PoseStamped& goal, Eigen::Vector2d* xy_m,
                               double* yaw_rad) {
  geometry_msgs::PoseStamped in_map = goal;
  if (!goal.header.frame_id.empty() && goal.header.frame_id != map_frame_) {
    try {
      // The goal stays where it was given: the latest transform, whatever the goal's stamp.
      geometry_msgs::PoseStamped latest = goal;
      latest.header.stamp = ros::Time(0);
      in_map = buffer_.transform(latest, map_frame_);
    } catch (const tf2::TransformException& e) {
      return Status::Error("goal frame '" + goal.header.frame_id + "' not on tf: " + e.what());
    }
  }
  *xy_m = Eigen::Vector2d(in_map.pose.position.x, in_map.pose.position.y);
  const auto& q = in_map.pose.orientation;  // yaw, whatever the quaternion's length
  *yaw_rad =
      std::atan2(2.0 * (q.w * q.z + q.x * q.y), q.w * q.w + q.x * q.x - q.y * q.y - q.z * q.z);
  return Status::Ok();
}

std::optional<Pose3> NavigationTf::FeedPose(GoalSession* session, std::string* error) {
  Pose3 pose;
  Time stamp;
  bool fix = false;
  const Status s = LocalizedBase(&pose, &stamp, &fix);
  if (!s.ok()) {
    *error = s.reason();
    return std::nullopt;
  }
  session->UpdatePose(stamp, pose, fix);
  return pose;
}

GoalCycleInputs NavigationTf::CycleInputs(GoalSession* session,
                                          const geometry_msgs::PoseStamped& goal,
                                          const std::string& camera_frame, double dt_s) {
  GoalCycleInputs in;
  in.now = ros_bridge::FromRos(ros::Time::now());
  in.dt_s = dt_s;
  in.wall_s = ros::WallTime::now().toSec();
  in.T_map_base = FeedPose(session, &in.pose_error);
  if (session->pending()) {
    double yaw_rad = 0.0;
    in.goal_status = GoalInMap(goal, &in.goal_m, &yaw_rad);
    in.goal_yaw_rad = yaw_rad;
    in.T_base_camera = Extrinsic(camera_frame);
    in.extrinsic_error = "no extrinsic (tf " + base_frame_ + " -> " + camera_frame + ")";
  }
  return in;
}

}  // namespace icgm::nodelets
