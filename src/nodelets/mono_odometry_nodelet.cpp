// Monocular odometry nodelet: the RGB stream (+ optional wheel odometry for the metric scale)
// -> core MonoOdometry (ICGM matches, essential-matrix initialization, PnP on a local map,
// windowed bundle adjustment; core/mono/mono_odometry.h) -> nav_msgs/Odometry and tf
// odom_frame -> child_frame (T_odom_camera). The scale state (metric from the wheels, or
// unknown) travels in the pose covariance (ros_bridge/mono_msgs.h).
// Images wait for the first camera_info (bounded); with ~wheel_odometry they also wait for the
// base -> camera extrinsic from tf (extrinsic_source.h) and for a wheel sample at or after
// their stamp, so the core gets the wheel samples up to each image before that image, as
// icgm_mono_vo --bag feeds them; once ~max_wait_frames images arrived without a wheel message
// in between, the wheels count as stopped and images go on without them.
#include <deque>
#include <memory>
#include <mutex>
#include <optional>

#include <nav_msgs/Odometry.h>
#include <nodelet/nodelet.h>
#include <ros/ros.h>
#include <sensor_msgs/CameraInfo.h>
#include <sensor_msgs/Image.h>
#include <tf2_ros/transform_broadcaster.h>
#include <boost/make_shared.hpp>
#include <pluginlib/class_list_macros.hpp>

#include "core/mono/mono_odometry.h"
#include "core/mono/mono_options.h"
#include "nodelets/cpu_meter.h"
#include "nodelets/extrinsic_source.h"
#include "ros_bridge/conversions.h"
#include "ros_bridge/mono_msgs.h"

namespace icgm_slam {

class MonoOdometryNodelet : public nodelet::Nodelet {
 private:
  void onInit() override {
    ros::NodeHandle& nh = getNodeHandle();
    ros::NodeHandle& pnh = getPrivateNodeHandle();
    // Parameters
    std::string config_file;
    pnh.param<std::string>("config_file", config_file, "");
    pnh.param<std::string>("odom_frame", msg_options_.odom_frame, msg_options_.odom_frame);
    pnh.param<std::string>("child_frame", msg_options_.child_frame, msg_options_.child_frame);
    pnh.param("sigma_position_m", msg_options_.sigma_position_m, msg_options_.sigma_position_m);
    pnh.param("sigma_rotation_rad", msg_options_.sigma_rotation_rad,
              msg_options_.sigma_rotation_rad);
    pnh.param("publish_tf", publish_tf_, true);
    pnh.param("queue_size", queue_size_, 200);
    pnh.param("camera_info_wait_s", camera_info_wait_s_, 5.0);
    pnh.param("wheel_odometry", use_wheels_, false);
    pnh.param("max_wait_frames", max_wait_frames_, 20);
    std::string base_frame;
    pnh.param<std::string>("base_frame", base_frame, "base_link");
    try {
      if (!config_file.empty()) options_ = icgm::LoadMonoOptions(config_file);
      bool use_icgm = options_.vo.use_icgm;
      if (pnh.getParam("use_icgm", use_icgm)) options_.vo.use_icgm = use_icgm;
    } catch (const icgm::LoadError& e) {
      NODELET_FATAL("mono odometry: bad configuration: %s", e.what());
      throw;
    }
    if (use_wheels_) {
      extrinsic_ = std::make_unique<icgm::nodelets::ExtrinsicSource>(
          pnh, base_frame, icgm::Pose3::Identity(), "mono odometry");
    }
    NODELET_INFO("mono odometry: %s, scale from %s", options_.vo.use_icgm ? "ICGM" : "no ICGM",
                 use_wheels_ ? "wheel odometry" : "nothing (unknown)");
    // Publications
    odom_pub_ = nh.advertise<nav_msgs::Odometry>("mono_odom", 50);
    // Subscriptions (eager: the map is state)
    if (use_wheels_) {
      wheel_sub_ = nh.subscribe("wheel_odom", 2000, &MonoOdometryNodelet::wheelCb, this);
    }
    info_sub_ = nh.subscribe("camera_info", 5, &MonoOdometryNodelet::infoCb, this);
    image_sub_ = nh.subscribe("image", queue_size_, &MonoOdometryNodelet::imageCb, this);
  }

  void infoCb(const sensor_msgs::CameraInfoConstPtr& msg) {
    std::lock_guard<std::mutex> lock(mutex_);
    if (intrinsics_) return;
    icgm::CameraIntrinsics k;
    if (icgm::Status s = icgm::ros_bridge::FromCameraInfo(*msg, 1000.0, &k); !s) {
      NODELET_WARN_THROTTLE(5.0, "mono odometry: bad camera_info: %s", s.reason().c_str());
      return;
    }
    intrinsics_ = k;
    drain();
  }

  void wheelCb(const nav_msgs::Odometry::ConstPtr& msg) {
    std::lock_guard<std::mutex> lock(mutex_);
    wheel_.push_back(msg);
    images_since_wheel_ = 0;
    drain();
  }

  void imageCb(const sensor_msgs::ImageConstPtr& msg) {
    std::lock_guard<std::mutex> lock(mutex_);
    if (!intrinsics_ && !first_image_) first_image_ = ros::WallTime::now();
    pending_.push_back(msg);
    ++images_since_wheel_;
    if (!intrinsics_ && (ros::WallTime::now() - *first_image_).toSec() >= camera_info_wait_s_) {
      NODELET_WARN_THROTTLE(5.0, "mono odometry: no valid camera_info after %.1f s; %zu images "
                                 "dropped", camera_info_wait_s_, pending_.size());
      pending_.clear();
    }
    drain();
  }

  // Processes the held images in order once the calibration (and the wheels) allow.
  void drain() {
    if (!intrinsics_ || pending_.empty()) return;
    if (!vo_) {
      if (use_wheels_) {
        const std::optional<icgm::Pose3> base_to_camera =
            extrinsic_->Poll(pending_.front()->header.frame_id);
        if (!base_to_camera && !extrinsic_->expired()) return;
        if (base_to_camera) {
          base_to_camera_ = *base_to_camera;
        } else {
          NODELET_ERROR("mono odometry: no base -> camera extrinsic: scale stays unknown");
        }
      }
      vo_ = std::make_unique<icgm::MonoOdometry>(options_, *intrinsics_);
      if (base_to_camera_) vo_->SetBaseToCamera(*base_to_camera_);
    }
    while (!pending_.empty()) {
      const sensor_msgs::ImageConstPtr image = pending_.front();
      const icgm::Time stamp = icgm::ros_bridge::FromRos(image->header.stamp);
      if (base_to_camera_) {
        const bool covered = !wheel_.empty() && wheel_.back()->header.stamp >= image->header.stamp;
        if (!covered && images_since_wheel_ <= max_wait_frames_) return;
        while (!wheel_.empty() && wheel_.front()->header.stamp <= image->header.stamp) {
          const icgm::Status s = vo_->AddWheelOdometry(
              icgm::ros_bridge::FromRos(wheel_.front()->header.stamp),
              icgm::ros_bridge::FromPoseMsg(wheel_.front()->pose.pose));
          if (!s.ok()) NODELET_WARN_THROTTLE(5.0, "mono odometry: wheel: %s", s.reason().c_str());
          wheel_.pop_front();
        }
      }
      pending_.pop_front();
      process(*image, stamp);
    }
  }

  void process(const sensor_msgs::Image& image, icgm::Time stamp) {
    cv::Mat bgr;
    if (icgm::Status s = icgm::ros_bridge::ColorFromImageMsg(image, &bgr); !s.ok()) {
      NODELET_WARN_THROTTLE(5.0, "mono odometry: dropped image: %s", s.reason().c_str());
      return;
    }
    if (last_stamp_ && stamp <= *last_stamp_) {
      NODELET_WARN("mono odometry: time went backwards (%s after %s); starting a new map",
                   stamp.ToString().c_str(), last_stamp_->ToString().c_str());
      vo_ = std::make_unique<icgm::MonoOdometry>(options_, *intrinsics_);
      if (base_to_camera_) vo_->SetBaseToCamera(*base_to_camera_);
      previous_.reset();
    }
    last_stamp_ = stamp;
    cpu_.Start();
    const icgm::MonoFrameResult r = vo_->ProcessFrame(stamp, bgr);
    if (double ms; cpu_.Stop(&ms)) {
      NODELET_INFO("mono odometry: %.1f ms CPU per frame (last 100), %zu keyframes, %zu resets",
                   ms, vo_->num_keyframes(), vo_->num_resets());
    }
    if (r.initialized) {
      NODELET_INFO("mono odometry: map initialized at %s (scale %s)", stamp.ToString().c_str(),
                   r.scale_known ? "metric" : "unknown");
    }
    if (r.reset) {
      NODELET_WARN("mono odometry: tracking lost, map reset at %s", stamp.ToString().c_str());
    }
    if (!r.has_pose) {
      NODELET_DEBUG("mono odometry: no pose at %s: %s", stamp.ToString().c_str(),
                    r.status.reason().c_str());
      if (r.reset) previous_.reset();
      return;
    }
    auto odom = boost::make_shared<nav_msgs::Odometry>(
        icgm::ros_bridge::ToMonoOdometryMsg(r, previous_, msg_options_));
    odom_pub_.publish(odom);
    if (publish_tf_) {
      geometry_msgs::TransformStamped t;
      t.header = odom->header;
      t.child_frame_id = odom->child_frame_id;
      t.transform = icgm::ros_bridge::ToTransformMsg(r.world_camera);
      tf_broadcaster_.sendTransform(t);
    }
    previous_ = icgm::ros_bridge::MonoPreviousPose{stamp, r.world_camera};
  }

  // Subscriptions
  ros::Subscriber image_sub_;
  ros::Subscriber info_sub_;
  ros::Subscriber wheel_sub_;
  // Publications
  ros::Publisher odom_pub_;
  tf2_ros::TransformBroadcaster tf_broadcaster_;
  // Parameters
  icgm::MonoOptions options_;
  icgm::ros_bridge::MonoOdometryMsgOptions msg_options_;
  bool publish_tf_ = true;
  int queue_size_ = 200;
  double camera_info_wait_s_ = 5.0;
  bool use_wheels_ = false;
  int max_wait_frames_ = 20;
  std::unique_ptr<icgm::nodelets::ExtrinsicSource> extrinsic_;
  // State
  std::mutex mutex_;  // image, camera_info and wheel callbacks may run on different threads
  std::optional<icgm::CameraIntrinsics> intrinsics_;  // the first valid camera_info
  std::optional<ros::WallTime> first_image_;
  std::optional<icgm::Pose3> base_to_camera_;
  std::deque<sensor_msgs::ImageConstPtr> pending_;
  std::deque<nav_msgs::Odometry::ConstPtr> wheel_;
  int images_since_wheel_ = 0;  // images received since the last wheel message
  std::unique_ptr<icgm::MonoOdometry> vo_;
  std::optional<icgm::Time> last_stamp_;
  std::optional<icgm::ros_bridge::MonoPreviousPose> previous_;
  icgm::nodelets::CpuMeter cpu_;
};

}  // namespace icgm_slam

PLUGINLIB_EXPORT_CLASS(icgm_slam::MonoOdometryNodelet, nodelet::Nodelet)
