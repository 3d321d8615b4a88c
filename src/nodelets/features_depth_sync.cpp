#include "nodelets/features_depth_sync.h"

#include <utility>

#include <boost/bind/bind.hpp>

namespace icgm::nodelets {

FeaturesDepthSync::FeaturesDepthSync(ros::NodeHandle& nh, int queue_size, bool approximate,
                                     Callback callback)
    : callback_(std::move(callback)) {
  features_.subscribe(nh, "features", queue_size);
  depth_.subscribe(nh, "depth", queue_size);
  // The synchronizer needs a callable with result_type: boost::bind, not a lambda.
  const auto cb = boost::bind(&FeaturesDepthSync::Forward, this, boost::placeholders::_1,
                              boost::placeholders::_2);
  if (approximate) {
    approx_ = std::make_unique<message_filters::Synchronizer<Approx>>(Approx(queue_size), features_,
                                                                      depth_);
    approx_->registerCallback(cb);
  } else {
    exact_ = std::make_unique<message_filters::Synchronizer<Exact>>(Exact(queue_size), features_,
                                                                    depth_);
    exact_->registerCallback(cb);
  }
}

}  // namespace icgm::nodelets
