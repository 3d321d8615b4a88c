#include "nodelets/nodelet_params.h"

#include <algorithm>
#include <map>
#include <mutex>
#include <set>

#include <opencv2/core/utility.hpp>
#include <ros/console.h>
#include <ros/param.h>

#include "core/common/option_reader.h"
#include "core/dataset/camera_options.h"
#include "nodelets/sensor_calibration.h"
#include "ros_bridge/conversions.h"

namespace icgm::nodelets {

namespace {

// The parameters each private namespace's nodelet reads (nodelets load on several threads).
std::mutex ledger_mutex;
std::map<std::string, std::set<std::string>>& Ledger() {
  static std::map<std::string, std::set<std::string>> ledger;
  return ledger;
}

size_t EditDistance(const std::string& a, const std::string& b) {
  std::vector<size_t> row(b.size() + 1);
  for (size_t j = 0; j <= b.size(); ++j) row[j] = j;
  for (size_t i = 1; i <= a.size(); ++i) {
    size_t diagonal = row[0];
    row[0] = i;
    for (size_t j = 1; j <= b.size(); ++j) {
      const size_t up = row[j];
      row[j] = std::min({row[j] + 1, row[j - 1] + 1, diagonal + (a[i - 1] != b[j - 1])});
      diagonal = up;
    }
  }
  return row[b.size()];
}

}  // namespace

void NoteParam(const ros::NodeHandle& pnh, const std::string& name) {
  std::lock_guard<std::mutex> lock(ledger_mutex);
  Ledger()[pnh.getNamespace()].insert(name);
}

std::vector<std::string> UnknownParams(const ros::NodeHandle& pnh) {
  std::vector<std::string> names;
  if (!ros::param::getParamNames(names)) return {};
  const std::string prefix = pnh.getNamespace() + "/";
  std::set<std::string> known;
  {
    std::lock_guard<std::mutex> lock(ledger_mutex);
    known = Ledger()[pnh.getNamespace()];
  }
  std::set<std::string> unknown;
  for (const std::string& full : names) {
    if (full.compare(0, prefix.size(), prefix) != 0) continue;
    const std::string name = full.substr(prefix.size());
    // A dictionary parameter's members are listed one by one; a sub-namespace is another's.
    const std::string head = name.substr(0, name.find('/'));
    if (known.count(head) || name.find('/') != std::string::npos) continue;
    std::string line = "~" + name;
    const std::string* best = nullptr;
    size_t best_distance = 3;
    for (const std::string& k : known) {
      const size_t d = EditDistance(name, k);
      if (d < best_distance) best_distance = d, best = &k;
    }
    if (best) line += " (did you mean ~" + *best + "?)";
    unknown.insert(line);
  }
  return {unknown.begin(), unknown.end()};
}

void WarnUnknownParams(const ros::NodeHandle& pnh, const std::string& who) {
  for (const std::string& p : UnknownParams(pnh)) {
    ROS_WARN("%s: unknown parameter %s, ignored (misspelt, or not a parameter of this nodelet)",
             who.c_str(), p.c_str());
  }
}

FrameNames ReadFrameNames(const ros::NodeHandle& pnh) {
  FrameNames f;
  f.map = Param(pnh, "map_frame", f.map);
  f.odom = Param(pnh, "odom_frame", f.odom);
  f.base = Param(pnh, "base_frame", f.base);
  return f;
}

void LoadConfiguration(const std::string& who, const std::function<void()>& load) {
  try {
    load();
  } catch (const LoadError& e) {
    ROS_FATAL("%s: bad configuration: %s", who.c_str(), e.what());
    throw;
  }
}

void ApplyOpenCvThreads(const ros::NodeHandle& pnh, const std::string& who) {
  const int threads = Param(pnh, "opencv_threads", 1);
  if (threads < 0) {
    ROS_ERROR("%s: ~opencv_threads %d < 0: OpenCV's thread count left as it is", who.c_str(),
              threads);
    return;
  }
  cv::setNumThreads(threads > 0 ? threads : -1);  // -1: OpenCV's default
}

CameraModelReader::CameraModelReader(const ros::NodeHandle& pnh, const std::string& who)
    : depth_scale_(Param(pnh, "depth_scale", 1000.0)) {
  std::string error;
  calibration_ = ReadSensorCalibration(pnh, &error);
  if (!error.empty()) ROS_ERROR("%s: %s (ignored)", who.c_str(), error.c_str());
}

Status CameraModelReader::Read(const sensor_msgs::CameraInfo& info, CameraIntrinsics* k) const {
  if (Status s = ros_bridge::FromCameraInfo(info, depth_scale_, k); !s.ok()) return s;
  CopySensorCalibration(calibration_, k);
  return Status::Ok();
}

}  // namespace icgm::nodelets
