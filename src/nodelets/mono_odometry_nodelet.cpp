// Monocular odometry nodelet: the RGB stream (+ optional wheel odometry for the metric scale)
// -> core MonoOdometry (core/mono/mono_odometry.h) -> nav_msgs/Odometry and tf odom_frame ->
// child_frame (T_odom_camera), the scale state in the pose covariance (ros_bridge/mono_msgs.h).
// Images wait for the first camera_info (bounded), with ~wheel_odometry also for the base ->
// camera extrinsic from tf (extrinsic_source.h) and for the wheel samples up to their stamp
// (core/mono/mono_input_queue.h, ~max_wait_frames), so the core gets what icgm_mono_vo --bag
// gives it. An image of another size than the camera_info is refused (throttled error with both
// sizes, the topic and the count so far), never back-projected with the wrong intrinsics.
#include <memory>
#include <mutex>
#include <optional>
#include <string>

#include <nav_msgs/Odometry.h>
#include <nodelet/nodelet.h>
#include <ros/ros.h>
#include <sensor_msgs/CameraInfo.h>
#include <sensor_msgs/Image.h>
#include <tf2_ros/transform_broadcaster.h>
#include <boost/make_shared.hpp>
#include <pluginlib/class_list_macros.hpp>

#include "core/mono/mono_input_queue.h"
#include "core/mono/mono_odometry.h"
#include "nodelets/cpu_meter.h"
#include "nodelets/extrinsic_source.h"
#include "nodelets/mono_odometry_params.h"
#include "nodelets/nodelet_params.h"
#include "ros_bridge/conversions.h"
#include "ros_bridge/image_size.h"
#include "ros_bridge/mono_msgs.h"

namespace icgm_slam {

class MonoOdometryNodelet : public nodelet::Nodelet {
 private:
  void onInit() override {
    ros::NodeHandle& nh = getNodeHandle();
    try {
      p_ = icgm::nodelets::ReadMonoOdometryParams(getPrivateNodeHandle());
    } catch (const icgm::LoadError& e) {
      NODELET_FATAL("mono odometry: bad configuration: %s", e.what());
      throw;
    }
    queue_ = std::make_unique<icgm::MonoInputQueue>(p_.wheel_odometry, p_.max_wait_frames);
    if (p_.wheel_odometry) {
      extrinsic_ = std::make_unique<icgm::nodelets::ExtrinsicSource>(
          getPrivateNodeHandle(), p_.base_frame, icgm::Pose3::Identity(), "mono odometry");
    }
    NODELET_INFO("mono odometry: %s, scale from %s", p_.options.vo.use_icgm ? "ICGM" : "no ICGM",
                 p_.wheel_odometry ? "wheel odometry" : "nothing (unknown)");
    // Publications
    odom_pub_ = nh.advertise<nav_msgs::Odometry>("mono_odom", 50);
    // Subscriptions (eager: the map is state)
    if (p_.wheel_odometry) {
      wheel_sub_ = nh.subscribe("wheel_odom", 2000, &MonoOdometryNodelet::wheelCb, this);
    }
    info_sub_ = nh.subscribe("camera_info", 5, &MonoOdometryNodelet::infoCb, this);
    image_sub_ = nh.subscribe("image", p_.queue_size, &MonoOdometryNodelet::imageCb, this);
    image_topic_ = image_sub_.getTopic();
    info_topic_ = info_sub_.getTopic();
    icgm::nodelets::WarnUnknownParams(getPrivateNodeHandle(), "mono odometry");
  }

  void infoCb(const sensor_msgs::CameraInfoConstPtr& msg) {
    std::lock_guard<std::mutex> lock(mutex_);
    icgm::CameraIntrinsics k;
    if (intrinsics_) return;
    if (icgm::Status s = icgm::ros_bridge::FromCameraInfo(*msg, 1000.0, &k); !s) {
      NODELET_WARN_THROTTLE(5.0, "mono odometry: bad camera_info: %s", s.reason().c_str());
      return;
    }
    intrinsics_ = k;
    drain();
  }

  void wheelCb(const nav_msgs::Odometry::ConstPtr& msg) {
    std::lock_guard<std::mutex> lock(mutex_);
    queue_->AddWheel(icgm::ros_bridge::FromRos(msg->header.stamp),
                     icgm::ros_bridge::FromPoseMsg(msg->pose.pose));
    drain();
  }

  void imageCb(const sensor_msgs::ImageConstPtr& msg) {
    std::lock_guard<std::mutex> lock(mutex_);
    cv::Mat bgr;
    if (icgm::Status s = icgm::ros_bridge::ColorFromImageMsg(*msg, &bgr); !s.ok()) {
      NODELET_WARN_THROTTLE(5.0, "mono odometry: dropped image: %s", s.reason().c_str());
      return;
    }
    if (camera_frame_.empty()) camera_frame_ = msg->header.frame_id;
    queue_->AddImage(icgm::ros_bridge::FromRos(msg->header.stamp), bgr);
    if (!intrinsics_ && !first_image_) first_image_ = ros::WallTime::now();
    if (!intrinsics_ && (ros::WallTime::now() - *first_image_).toSec() >= p_.camera_info_wait_s) {
      NODELET_WARN_THROTTLE(5.0,
                            "mono odometry: no valid camera_info after %.1f s; %zu images "
                            "dropped",
                            p_.camera_info_wait_s, queue_->DropImages());
    }
    drain();
  }

  // Processes the held images in order once the calibration (and the wheels) allow.
  void drain() {
    if (!intrinsics_ || queue_->num_images() == 0) return;
    if (!vo_) {
      if (extrinsic_) {
        base_to_camera_ = extrinsic_->Poll(camera_frame_);
        if (!base_to_camera_ && !extrinsic_->expired()) return;
        if (!base_to_camera_)
          NODELET_ERROR("mono odometry: no base -> camera extrinsic: scale unknown");
      }
      restart();
    }
    for (icgm::MonoInput in; queue_->Pop(&in);) {
      for (const icgm::StampedPose& w : in.wheel) {
        const icgm::Status s = vo_->AddWheelOdometry(w.stamp, w.pose);
        if (!s.ok()) NODELET_WARN_THROTTLE(5.0, "mono odometry: wheel: %s", s.reason().c_str());
      }
      if (const icgm::Status fits =
              icgm::ros_bridge::CheckImageSize(in.image, image_topic_, *intrinsics_, info_topic_);
          !fits.ok()) {
        NODELET_ERROR_THROTTLE(5.0, "mono odometry: image refused (%zu so far): %s", ++refused_,
                               fits.reason().c_str());
        continue;
      }
      process(in);
    }
  }

  void restart() {
    vo_ = std::make_unique<icgm::MonoOdometry>(p_.options, *intrinsics_);
    if (base_to_camera_) vo_->SetBaseToCamera(*base_to_camera_);
    previous_.reset();
  }

  void process(const icgm::MonoInput& in) {
    if (last_stamp_ && in.stamp <= *last_stamp_) {
      NODELET_WARN("mono odometry: time went backwards (%s after %s); starting a new map",
                   in.stamp.ToString().c_str(), last_stamp_->ToString().c_str());
      restart();
    }
    last_stamp_ = in.stamp;
    cpu_.Start();
    const icgm::MonoFrameResult r = vo_->ProcessFrame(in.stamp, in.image);
    if (double ms; cpu_.Stop(&ms)) {
      NODELET_INFO("mono odometry: %.1f ms CPU per frame (last 100), %zu keyframes, %zu resets", ms,
                   vo_->num_keyframes(), vo_->num_resets());
    }
    if (r.initialized)
      NODELET_INFO("mono odometry: map initialized (scale %s)",
                   r.scale_known ? "metric" : "unknown");
    if (r.reset)
      NODELET_WARN("mono odometry: tracking lost, map reset at %s", in.stamp.ToString().c_str());
    if (r.reset && !r.has_pose) previous_.reset();
    if (!r.has_pose) return;
    auto odom = boost::make_shared<nav_msgs::Odometry>(
        icgm::ros_bridge::ToMonoOdometryMsg(r, previous_, p_.msg));
    odom_pub_.publish(odom);
    if (p_.publish_tf)
      tf_broadcaster_.sendTransform(icgm::ros_bridge::MonoOdometryTransform(*odom));
    previous_ = icgm::ros_bridge::MonoPreviousPose{in.stamp, r.world_camera};
  }

  // Subscriptions
  ros::Subscriber image_sub_, info_sub_, wheel_sub_;
  // Publications
  ros::Publisher odom_pub_;
  tf2_ros::TransformBroadcaster tf_broadcaster_;
  // Parameters
  icgm::nodelets::MonoOdometryParams p_;
  std::unique_ptr<icgm::nodelets::ExtrinsicSource> extrinsic_;
  // State
  std::mutex mutex_;  // image, camera_info and wheel callbacks may run on different threads
  std::unique_ptr<icgm::MonoInputQueue> queue_;
  std::optional<icgm::CameraIntrinsics> intrinsics_;  // the first valid camera_info
  std::string image_topic_, info_topic_;               // resolved, for the size check's errors
  size_t refused_ = 0;                                 // images of another size than it
  std::optional<ros::WallTime> first_image_;
  std::string camera_frame_;
  std::optional<icgm::Pose3> base_to_camera_;
  std::unique_ptr<icgm::MonoOdometry> vo_;
  std::optional<icgm::Time> last_stamp_;
  std::optional<icgm::ros_bridge::MonoPreviousPose> previous_;
  icgm::nodelets::CpuMeter cpu_;
};

}  // namespace icgm_slam

PLUGINLIB_EXPORT_CLASS(icgm_slam::MonoOdometryNodelet, nodelet::Nodelet)
