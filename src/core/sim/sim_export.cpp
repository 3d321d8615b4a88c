#include "core/sim/sim_export.h"

#include <cmath>
#include <cstdint>

namespace icgm::sim {

cv::Mat DepthToMillimetres(const cv::Mat& depth_m) {
  CV_Assert(depth_m.type() == CV_32FC1);
  cv::Mat mm(depth_m.size(), CV_16UC1);
  for (int v = 0; v < depth_m.rows; ++v) {
    const float* in = depth_m.ptr<float>(v);
    uint16_t* out = mm.ptr<uint16_t>(v);
    for (int u = 0; u < depth_m.cols; ++u) {
      const float z = in[u];
      const float value = std::round(z * 1000.0f);
      // NaN fails both comparisons and becomes 0.
      out[u] = (value >= 1.0f && value <= 65535.0f) ? static_cast<uint16_t>(value) : 0;
    }
  }
  return mm;
}

Trajectory CameraGroundTruth(const Simulator& sim) {
  Trajectory t;
  t.reserve(sim.size());
  for (size_t i = 0; i < sim.size(); ++i) t.push_back({sim.stamp(i), sim.T_world_camera(i)});
  return t;
}

Trajectory WheelOdometryTrajectory(const Simulator& sim) {
  Trajectory t;
  if (!sim.has_wheel_odometry()) return t;
  t.reserve(sim.size());
  for (size_t i = 0; i < sim.size(); ++i) {
    t.push_back({sim.stamp(i), sim.odometry(i).T_odom_base});
  }
  return t;
}

std::string SidecarPath(const std::string& bag_path, const std::string& suffix) {
  const std::string ext = ".bag";
  if (bag_path.size() > ext.size() &&
      bag_path.compare(bag_path.size() - ext.size(), ext.size(), ext) == 0) {
    return bag_path.substr(0, bag_path.size() - ext.size()) + suffix;
  }
  return bag_path + suffix;
}

}  // namespace icgm::sim
