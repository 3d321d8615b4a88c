// The features of a frame with its registered depth, matched by stamp (message_filters,
// approximate or exact time), for the nodelets that lift keypoints with depth. camera_info is not
// part of the match: the camera is fixed once (the registration takes it separately), so a frame
// costs two messages through the manager, not three.
#pragma once

#include <functional>
#include <memory>

#include <icgm_slam/RobustFeatures.h>
#include <message_filters/subscriber.h>
#include <message_filters/sync_policies/approximate_time.h>
#include <message_filters/sync_policies/exact_time.h>
#include <message_filters/synchronizer.h>
#include <ros/node_handle.h>
#include <sensor_msgs/Image.h>

namespace icgm::nodelets {

class FeaturesDepthSync {
 public:
  using Features = icgm_slam::RobustFeatures;
  using Image = sensor_msgs::Image;
  using Callback = std::function<void(const Features::ConstPtr&, const Image::ConstPtr&)>;

  // Subscribes to `features` and `depth` of `nh`.
  FeaturesDepthSync(ros::NodeHandle& nh, int queue_size, bool approximate, Callback callback);

 private:
  using Approx = message_filters::sync_policies::ApproximateTime<Features, Image>;
  using Exact = message_filters::sync_policies::ExactTime<Features, Image>;
  void Forward(const Features::ConstPtr& f, const Image::ConstPtr& d) { callback_(f, d); }

  Callback callback_;
  message_filters::Subscriber<Features> features_;
  message_filters::Subscriber<Image> depth_;
  std::unique_ptr<message_filters::Synchronizer<Approx>> approx_;
  std::unique_ptr<message_filters::Synchronizer<Exact>> exact_;
};

}  // namespace icgm::nodelets
