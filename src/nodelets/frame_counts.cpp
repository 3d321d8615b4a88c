#include "nodelets/frame_counts.h"

#include <utility>

#include <diagnostic_msgs/DiagnosticArray.h>

namespace icgm::nodelets {

FrameCounts::FrameCounts(ros::NodeHandle& nh, const std::string& name,
                         std::vector<std::string> keys)
    : name_(name + ": frames"), keys_(std::move(keys)), counts_(keys_.size(), 0) {
  pub_ = nh.advertise<diagnostic_msgs::DiagnosticArray>("/diagnostics", 10);
  timer_ =
      nh.createWallTimer(ros::WallDuration(1.0), [this](const ros::WallTimerEvent&) { Publish(); });
}

void FrameCounts::Add(size_t key, size_t n) {
  std::lock_guard<std::mutex> lock(mutex_);
  counts_.at(key) += n;
  changed_ = true;
}

void FrameCounts::Set(size_t key, size_t value) {
  std::lock_guard<std::mutex> lock(mutex_);
  changed_ = changed_ || counts_.at(key) != value;
  counts_.at(key) = value;
}

void FrameCounts::Publish() {
  diagnostic_msgs::DiagnosticArray array;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    if (!changed_) return;
    changed_ = false;
    diagnostic_msgs::DiagnosticStatus status;
    status.level = diagnostic_msgs::DiagnosticStatus::OK;
    status.name = name_;
    for (size_t i = 0; i < keys_.size(); ++i) {
      diagnostic_msgs::KeyValue kv;
      kv.key = keys_[i];
      kv.value = std::to_string(counts_[i]);
      status.values.push_back(kv);
    }
    array.status.push_back(status);
  }
  array.header.stamp = ros::Time::now();
  pub_.publish(array);
}

}  // namespace icgm::nodelets
