// RGB-D registration nodelet: ICGM-kept matches of each frame to its reference frame (from the
// feature extraction nodelet) + registered depth + camera_info -> relative 6D pose by RANSAC +
// Horn (icgm_slam/RegistrationResult). A failed registration is published too, with its reason,
// so the fusion can fall back to wheel odometry for that span.
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
#include "core/registration/rgbd_registration.h"
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
    pnh.param("queue_size", queue_size_, 10);
    pnh.param("approx_sync", approx_sync_, true);
    pnh.param("depth_scale", depth_scale_, 1000.0);
    try {
      if (!config_file.empty()) {
        icgm::ReadOptions(icgm::OptionReader::FromFile(config_file).Section("registration"),
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
    Frame cur;
    if (icgm::Status s = icgm::ros_bridge::FromFeaturesMsg(*features_msg, &cur.features); !s) {
      NODELET_WARN_THROTTLE(5.0, "rgbd registration: bad features: %s", s.reason().c_str());
      return;
    }
    if (icgm::Status s = icgm::ros_bridge::DepthFromImageMsg(*depth_msg, depth_scale_, &cur.depth_m);
        !s) {
      NODELET_WARN_THROTTLE(5.0, "rgbd registration: bad depth: %s", s.reason().c_str());
      return;
    }
    icgm::CameraIntrinsics k;
    if (icgm::Status s = icgm::ros_bridge::FromCameraInfo(*info_msg, depth_scale_, &k); !s) {
      NODELET_WARN_THROTTLE(5.0, "rgbd registration: bad camera_info: %s", s.reason().c_str());
      return;
    }
    const icgm::Time reference = icgm::ros_bridge::FromRos(features_msg->reference_header.stamp);
    if (prev_ && cur.features.stamp <= prev_->features.stamp) {
      NODELET_WARN("rgbd registration: time went backwards; dropping the reference frame");
      prev_.reset();
    }
    if (prev_) {
      icgm::RegistrationResult result;
      if (prev_->features.stamp != reference) {
        result.status = icgm::Status::Error("reference frame " + reference.ToString() +
                                            " was not received (have " +
                                            prev_->features.stamp.ToString() + ")");
      } else {
        std::vector<cv::Point2f> pts_ref, pts_cur;
        const auto& f = cur.features;
        for (size_t m = 0; m < f.matches_to_previous.size(); ++m) {
          if (!f.match_kept[m]) continue;
          const cv::DMatch& d = f.matches_to_previous[m];
          if (static_cast<size_t>(d.trainIdx) >= prev_->features.features.keypoints.size()) {
            continue;
          }
          pts_cur.push_back(f.features.keypoints[d.queryIdx].pt);
          pts_ref.push_back(prev_->features.features.keypoints[d.trainIdx].pt);
        }
        result = icgm::RegisterRgbd(pts_ref, prev_->depth_m, pts_cur, cur.depth_m, k, options_);
      }
      if (!result.status.ok()) {
        NODELET_DEBUG("rgbd registration: %s", result.status.reason().c_str());
      }
      result_pub_.publish(icgm::ros_bridge::ToRegistrationMsg(
          result, cur.features.stamp, prev_->features.stamp, features_msg->header.frame_id));
    }
    prev_ = std::move(cur);
  }

  struct Frame {
    icgm::TrackedFrame features;
    cv::Mat depth_m;
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
  icgm::RegistrationOptions options_;
  // State
  std::optional<Frame> prev_;
};

}  // namespace icgm_slam

PLUGINLIB_EXPORT_CLASS(icgm_slam::RgbdRegistrationNodelet, nodelet::Nodelet)
