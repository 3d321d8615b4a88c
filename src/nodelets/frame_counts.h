// Frame counts of a pipeline nodelet (frames in, skipped, dropped and out at its stage) on
// /diagnostics (diagnostic_msgs/DiagnosticArray with one status named "<nodelet name>: frames",
// one value per count), at most once a second of wall time and only after a count changed: what
// tells where the frames a pipeline did not answer went (launch_scripts/benchmark_live.sh).
#pragma once

#include <cstddef>
#include <mutex>
#include <string>
#include <vector>

#include <ros/node_handle.h>
#include <ros/publisher.h>
#include <ros/wall_timer.h>

namespace icgm::nodelets {

class FrameCounts {
 public:
  // `keys`: the counts' names, in the order Add takes their indices.
  FrameCounts(ros::NodeHandle& nh, const std::string& name, std::vector<std::string> keys);
  // Thread-safe.
  void Add(size_t key, size_t n = 1);
  void Set(size_t key, size_t value);

 private:
  void Publish();

  std::string name_;
  std::vector<std::string> keys_;
  std::mutex mutex_;
  std::vector<size_t> counts_;
  bool changed_ = false;
  ros::Publisher pub_;
  ros::WallTimer timer_;
};

}  // namespace icgm::nodelets
