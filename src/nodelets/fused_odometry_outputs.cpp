#include "nodelets/fused_odometry_outputs.h"

#include <boost/make_shared.hpp>

#include <geometry_msgs/TransformStamped.h>
#include <nav_msgs/Odometry.h>

#include "ros_bridge/conversions.h"

namespace icgm::nodelets {

FusedOdometryOutputs::FusedOdometryOutputs(ros::NodeHandle& nh, const ros::NodeHandle& pnh,
                                           const FrameNames& frames)
    : odom_pub_(nh.advertise<nav_msgs::Odometry>("odom", 50)), frames_(frames) {
  publish_tf_ = Param(pnh, "publish_tf", true);
  fallback_.floor_m = Param(pnh, "fallback_sigma_floor_m", fallback_.floor_m);
  fallback_.floor_rad = Param(pnh, "fallback_sigma_floor_rad", fallback_.floor_rad);
  fallback_.per_m = Param(pnh, "fallback_sigma_per_m", fallback_.per_m);
}

void FusedOdometryOutputs::Start(const ros::Time& stamp, const OdometryFusion& fusion,
                                 const std::string& child_frame) {
  child_frame_ = child_frame;
  PublishTf(stamp, fusion);
}

void FusedOdometryOutputs::Publish(const FusedResult& f, const OdometryFusion& fusion) {
  const Mat6 step_covariance =
      ros_bridge::FusedStepCovariance(f.step, f.registration->covariance, fallback_);
  covariance_.AddStep(f.odom_camera_before, fusion.odom_camera(), step_covariance);
  if (f.step.source != MotionSource::kVision) {
    ROS_DEBUG("odometry fusion: %s motion at %s (vision: %s; wheel: %s)",
              MotionSourceName(f.step.source), f.stamp.ToString().c_str(),
              f.registration->status.reason().c_str(), f.step.wheel_status.reason().c_str());
  }
  const Pose3& base_to_camera = fusion.options().base_to_camera;
  const ros::Time stamp = ros_bridge::ToRos(f.stamp);
  // A shared pointer: no serialization for subscribers in the same manager.
  odom_pub_.publish(boost::make_shared<nav_msgs::Odometry>(ros_bridge::ToFusedOdometryMsg(
      stamp, frames_.odom, child_frame_, fusion.odom_base(),
      covariance_.BaseMsg(fusion.odom_camera(), base_to_camera),
      ros_bridge::BaseStepTwist(f.step.camera_prev_cur, step_covariance, base_to_camera, f.dt_s))));
  PublishTf(stamp, fusion);
  const FusionStats& stats = fusion.stats();
  if (stats.total_frames() % 100 == 0) {
    ROS_INFO("odometry fusion: %zu frames, vision share %.1f%% of frames, %.1f%% of distance",
             stats.total_frames(), 100 * stats.VisionShareByFrames(),
             100 * stats.VisionShareByDistance());
  }
}

void FusedOdometryOutputs::PublishTf(const ros::Time& stamp, const OdometryFusion& fusion) {
  if (!publish_tf_) return;
  geometry_msgs::TransformStamped t;
  t.header.stamp = stamp;
  t.header.frame_id = frames_.odom;
  t.child_frame_id = child_frame_;
  t.transform = ros_bridge::ToTransformMsg(fusion.odom_base());
  tf_broadcaster_.sendTransform(t);
}

}  // namespace icgm::nodelets
