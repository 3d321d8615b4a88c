// The features of a frame with its registered depth and camera_info, matched by stamp
// (message_filters, approximate or exact time), for the nodelets that lift keypoints with depth.
#pragma once

#include <functional>
#include <memory>

#include <icgm_slam/RobustFeatures.h>
#include <message_filters/subscriber.h>
#include <message_filters/sync_policies/approximate_time.h>
#include <message_filters/sync_policies/exact_time.h>
#include <message_filters/synchronizer.h>
#include <ros/node_handle.h>
#include <sensor_msgs/CameraInfo.h>
#include <sensor_msgs/Image.h>

namespace icgm::nodelets {

class FeaturesDepthSync {
 public:
  using Features = icgm_slam::RobustFeatures;
  using Image = sensor_msgs::Image;
  using Info = sensor_msgs::CameraInfo;
  using Callback = std::function<void(const Features::ConstPtr&, const Image::ConstPtr&,
                                      const Info::ConstPtr&)>;

  // Subscribes to `features`, `depth` and `camera_info` of `nh`.
  FeaturesDepthSync(ros::NodeHandle& nh, int queue_size, bool approximate, Callback callback);

 private:
  using Approx = message_filters::sync_policies::ApproximateTime<Features, Image, Info>;
  using Exact = message_filters::sync_policies::ExactTime<Features, Image, Info>;
  void Forward(const Features::ConstPtr& f, const Image::ConstPtr& d, const Info::ConstPtr& i) {
    callback_(f, d, i);
  }

  Callback callback_;
  message_filters::Subscriber<Features> features_;
  message_filters::Subscriber<Image> depth_;
  message_filters::Subscriber<Info> info_;
  std::unique_ptr<message_filters::Synchronizer<Approx>> approx_;
  std::unique_ptr<message_filters::Synchronizer<Exact>> exact_;
};

}  // namespace icgm::nodelets
