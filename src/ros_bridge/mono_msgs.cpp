#include "ros_bridge/mono_msgs.h"

#include <Eigen/Geometry>

#include "ros_bridge/conversions.h"

namespace icgm::ros_bridge {

nav_msgs::Odometry ToMonoOdometryMsg(const MonoFrameResult& result,
                                     const std::optional<MonoPreviousPose>& previous,
                                     const MonoOdometryMsgOptions& options) {
  nav_msgs::Odometry msg;
  msg.header.stamp = ToRos(result.stamp);
  msg.header.frame_id = options.odom_frame;
  msg.child_frame_id = options.child_frame;
  msg.pose.pose = ToPoseMsg(result.world_camera);
  const double position_variance = result.scale_known
                                       ? options.sigma_position_m * options.sigma_position_m
                                       : kUnknownScaleVariance;
  const double rotation_variance = options.sigma_rotation_rad * options.sigma_rotation_rad;
  for (int i = 0; i < 3; ++i) {
    msg.pose.covariance[i * 7] = position_variance;
    msg.pose.covariance[(i + 3) * 7] = rotation_variance;
  }
  // Twist of the child frame in its own axes over the last step.
  const double dt_s = previous ? DurationSeconds(result.stamp, previous->stamp) : 0.0;
  if (dt_s > 0.0) {
    const Pose3 step = previous->world_camera.inverse() * result.world_camera;
    const Eigen::AngleAxisd rotation(step.linear());
    const Vec3 linear = result.world_camera.linear().transpose() *
                        (result.world_camera.translation() - previous->world_camera.translation()) /
                        dt_s;
    const Vec3 angular = rotation.angle() * rotation.axis() / dt_s;
    msg.twist.twist.linear.x = linear.x();
    msg.twist.twist.linear.y = linear.y();
    msg.twist.twist.linear.z = linear.z();
    msg.twist.twist.angular.x = angular.x();
    msg.twist.twist.angular.y = angular.y();
    msg.twist.twist.angular.z = angular.z();
    for (int i = 0; i < 3; ++i) {
      msg.twist.covariance[i * 7] =
          result.scale_known ? position_variance / (dt_s * dt_s) : kUnknownScaleVariance;
      msg.twist.covariance[(i + 3) * 7] = rotation_variance / (dt_s * dt_s);
    }
  } else {
    for (int i = 0; i < 6; ++i) msg.twist.covariance[i * 7] = kUnknownScaleVariance;
  }
  return msg;
}

geometry_msgs::TransformStamped MonoOdometryTransform(const nav_msgs::Odometry& msg) {
  geometry_msgs::TransformStamped t;
  t.header = msg.header;
  t.child_frame_id = msg.child_frame_id;
  t.transform = ToTransformMsg(FromPoseMsg(msg.pose.pose));
  return t;
}

bool MonoScaleKnown(const nav_msgs::Odometry& msg) {
  return msg.pose.covariance[0] < kUnknownScaleVariance;
}

}  // namespace icgm::ros_bridge
