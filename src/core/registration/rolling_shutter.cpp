#include "core/registration/rolling_shutter.h"

#include <algorithm>
#include <cmath>

namespace icgm {

std::vector<Pose3> StampFromRowPoses(int rows, const RowTiming& timing,
                                     const Vec6& twist_per_s) {
  std::vector<Pose3> out;
  out.reserve(std::max(rows, 0));
  for (int v = 0; v < rows; ++v) out.push_back(ExpSE3(timing.RowOffsetS(v) * twist_per_s));
  return out;
}

void DeskewKeypoints(const std::vector<Pose3>& stamp_from_row, const cv::Mat& depth_stamp_m,
                     const CameraIntrinsics& k, std::vector<cv::KeyPoint>* keypoints) {
  const int rows = static_cast<int>(stamp_from_row.size());
  const bool has_depth = !depth_stamp_m.empty() && depth_stamp_m.type() == CV_32FC1;
  for (cv::KeyPoint& kp : *keypoints) {
    const int u = static_cast<int>(std::lround(kp.pt.x));
    const int v = static_cast<int>(std::lround(kp.pt.y));
    if (v < 0 || v >= rows || u < 0 || u >= k.width_px) continue;
    const Pose3& t = stamp_from_row[v];
    float z = 0.0f;
    if (has_depth && v < depth_stamp_m.rows && u < depth_stamp_m.cols) {
      z = depth_stamp_m.at<float>(v, u);
    }
    Eigen::Vector3d p;
    if (z > 0.0f && std::isfinite(z)) {
      p = t * k.BackProject(kp.pt.x, kp.pt.y, z);
    } else {
      p = t.linear() * k.BackProject(kp.pt.x, kp.pt.y, 1.0);
    }
    if (!(p.z() > 1e-6)) continue;
    const Eigen::Vector2d q = k.Project(p);
    kp.pt = cv::Point2f(static_cast<float>(q.x()), static_cast<float>(q.y()));
  }
}

}  // namespace icgm
