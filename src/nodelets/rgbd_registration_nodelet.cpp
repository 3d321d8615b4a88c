// RGB-D registration nodelet: the features of each frame (from the feature extraction nodelet)
// + registered depth + camera_info -> relative 6D pose of the camera since the previous frame
// (icgm_slam/RegistrationResult). Registration runs frame-to-keyframe in the core front end
// (descriptor matching -> ICGM -> RANSAC + Horn on depth -> refinement), as the offline tools
// do. A failed registration is published too, with its reason, so the fusion can fall back to
// wheel odometry for that span.
#include <memory>
#include <optional>

#include <boost/bind/bind.hpp>

#include <message_filters/subscriber.h>
#include <message_filters/sync_policies/approximate_time.h>
#include <message_filters/sync_policies/exact_time.h>
#include <message_filters/synchronizer.h>
#include <nodelet/nodelet.h>
#include <pluginlib/class_list_macros.hpp>
#include <ros/ros.h>
#include <sensor_msgs/CameraInfo.h>
#include <sensor_msgs/Image.h>

#include "core/common/option_reader.h"
#include "core/dataset/camera_options.h"
#include "core/odometry/rgbd_frontend.h"
#include "nodelets/sensor_calibration.h"
#include "ros_bridge/conversions.h"
#include "ros_bridge/feature_msgs.h"
#include "ros_bridge/registration_msgs.h"

namespace icgm_slam {

class RgbdRegistrationNodelet : public nodelet::Nodelet {
 private:
  using Features = icgm_slam::RobustFeatures;
  using Image = sensor_msgs::Image;
  using Info = sensor_msgs::CameraInfo;
  using ApproxPolicy = message_filters::sync_policies::ApproximateTime<Features, Image, Info>;
  using ExactPolicy = message_filters::sync_policies::ExactTime<Features, Image, Info>;

  void onInit() override {
    ros::NodeHandle& nh = getNodeHandle();
    ros::NodeHandle& pnh = getPrivateNodeHandle();
    // Parameters
    std::string config_file;
    pnh.param<std::string>("config_file", config_file, "");
    pnh.param<std::string>("icgm_config_file", icgm_config_file_, "");
    pnh.param("queue_size", queue_size_, 10);
    pnh.param("approx_sync", approx_sync_, true);
    pnh.param("depth_scale", depth_scale_, 1000.0);
    // Depth timing and scale, rolling shutter: ~camera_config_file and single parameters.
    std::string calibration_error;
    sensor_calibration_ = icgm::nodelets::ReadSensorCalibration(pnh, &calibration_error);
    if (!calibration_error.empty()) {
      NODELET_ERROR("rgbd registration: %s (ignored)", calibration_error.c_str());
    }
    try {
      if (!config_file.empty()) {
        const auto odometry = icgm::OptionReader::FromFile(config_file);
        icgm::ReadFrontendOptions(odometry, icgm_config_file_.empty()
                                                ? odometry
                                                : icgm::OptionReader::FromFile(icgm_config_file_),
                                  &options_);
      }
    } catch (const icgm::LoadError& e) {
      NODELET_FATAL("rgbd registration: bad configuration: %s", e.what());
      throw;
    }
    // Publications
    result_pub_ = nh.advertise<icgm_slam::RegistrationResult>("relative_pose", 20);
    // Subscriptions (eager: the previous frame is state)
    features_sub_.subscribe(nh, "features", queue_size_);
    depth_sub_.subscribe(nh, "depth", queue_size_);
    info_sub_.subscribe(nh, "camera_info", queue_size_);
    // Synchronizer needs a callable with result_type: boost::bind, not a lambda.
    const auto cb = boost::bind(&RgbdRegistrationNodelet::frameCb, this, boost::placeholders::_1,
                                boost::placeholders::_2, boost::placeholders::_3);
    if (approx_sync_) {
      approx_sync_ptr_ = std::make_unique<message_filters::Synchronizer<ApproxPolicy>>(
          ApproxPolicy(queue_size_), features_sub_, depth_sub_, info_sub_);
      approx_sync_ptr_->registerCallback(cb);
    } else {
      exact_sync_ptr_ = std::make_unique<message_filters::Synchronizer<ExactPolicy>>(
          ExactPolicy(queue_size_), features_sub_, depth_sub_, info_sub_);
      exact_sync_ptr_->registerCallback(cb);
    }
  }

  void frameCb(const Features::ConstPtr& features_msg, const Image::ConstPtr& depth_msg,
               const Info::ConstPtr& info_msg) {
    icgm::TrackedFrame frame;
    if (icgm::Status s = icgm::ros_bridge::FromFeaturesMsg(*features_msg, &frame); !s) {
      NODELET_WARN_THROTTLE(5.0, "rgbd registration: bad features: %s", s.reason().c_str());
      return;
    }
    cv::Mat depth_m;
    if (icgm::Status s = icgm::ros_bridge::DepthFromImageMsg(*depth_msg, depth_scale_, &depth_m);
        !s) {
      NODELET_WARN_THROTTLE(5.0, "rgbd registration: bad depth: %s", s.reason().c_str());
      return;
    }
    if (!frontend_) {
      icgm::CameraIntrinsics k;
      if (icgm::Status s = icgm::ros_bridge::FromCameraInfo(*info_msg, depth_scale_, &k); !s) {
        NODELET_WARN_THROTTLE(5.0, "rgbd registration: bad camera_info: %s", s.reason().c_str());
        return;
      }
      icgm::CopySensorCalibration(sensor_calibration_, &k);
      frontend_ = std::make_unique<icgm::RgbdFrontend>(options_, k);
    }
    const icgm::FrontendFrameResult r =
        frontend_->ProcessFeatures(frame.stamp, std::move(frame.features), depth_m,
                                   icgm::ros_bridge::FromRos(depth_msg->header.stamp));
    if (!r.status.ok()) {
      NODELET_WARN_THROTTLE(5.0, "rgbd registration: frame dropped: %s", r.status.reason().c_str());
      return;
    }
    if (previous_) {
      // The front end holds the pose (no wheel data here); only vision counts as a success.
      icgm::RegistrationResult result = r.registration;
      if (r.source == icgm::MotionSource::kVision) {
        result.status = icgm::Status::Ok();
        result.relative_pose = icgm::Between(previous_->odom_camera, r.odom_camera);
      } else if (result.status.ok()) {
        result.status = icgm::Status::Error("no vision motion for this frame");
      }
      result_pub_.publish(icgm::ros_bridge::ToRegistrationMsg(
          result, r.stamp, previous_->stamp, features_msg->header.frame_id));
    }
    previous_ = Previous{r.stamp, r.odom_camera};
  }

  struct Previous {
    icgm::Time stamp;
    icgm::Pose3 odom_camera;
  };

  // Subscriptions
  message_filters::Subscriber<Features> features_sub_;
  message_filters::Subscriber<Image> depth_sub_;
  message_filters::Subscriber<Info> info_sub_;
  std::unique_ptr<message_filters::Synchronizer<ApproxPolicy>> approx_sync_ptr_;
  std::unique_ptr<message_filters::Synchronizer<ExactPolicy>> exact_sync_ptr_;
  // Publications
  ros::Publisher result_pub_;
  // Parameters
  int queue_size_ = 10;
  bool approx_sync_ = true;
  double depth_scale_ = 1000.0;
  icgm::CameraIntrinsics sensor_calibration_;  // camera_info lacks these fields
  std::string icgm_config_file_;
  icgm::FrontendOptions options_;
  // State
  std::unique_ptr<icgm::RgbdFrontend> frontend_;
  std::optional<Previous> previous_;
};

}  // namespace icgm_slam

PLUGINLIB_EXPORT_CLASS(icgm_slam::RgbdRegistrationNodelet, nodelet::Nodelet)
