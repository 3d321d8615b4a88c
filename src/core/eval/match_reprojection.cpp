#include "core/eval/match_reprojection.h"

#include <cmath>
#include <limits>

namespace icgm {

std::vector<double> MatchReprojectionErrorsPx(const std::vector<cv::KeyPoint>& a,
                                              const std::vector<cv::KeyPoint>& b,
                                              const std::vector<cv::DMatch>& matches,
                                              const cv::Mat& depth_a_m,
                                              const CameraIntrinsics& intrinsics,
                                              const Pose3& b_from_a) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  std::vector<double> errors(matches.size(), nan);
  if (depth_a_m.empty() || depth_a_m.type() != CV_32FC1) return errors;
  for (size_t k = 0; k < matches.size(); ++k) {
    const cv::DMatch& m = matches[k];
    if (m.queryIdx < 0 || m.queryIdx >= static_cast<int>(a.size()) || m.trainIdx < 0 ||
        m.trainIdx >= static_cast<int>(b.size())) {
      continue;
    }
    const cv::Point2f pa = a[m.queryIdx].pt;
    const int x = static_cast<int>(std::lround(pa.x));
    const int y = static_cast<int>(std::lround(pa.y));
    if (x < 0 || y < 0 || x >= depth_a_m.cols || y >= depth_a_m.rows) continue;
    const float z = depth_a_m.at<float>(y, x);
    if (!(z > 0.0f)) continue;  // NaN or invalid
    const Eigen::Vector3d in_b = b_from_a * intrinsics.BackProject(pa.x, pa.y, z);
    if (in_b.z() <= 1e-6) continue;
    const Eigen::Vector2d uv = intrinsics.Project(in_b);
    const cv::Point2f pb = b[m.trainIdx].pt;
    errors[k] = std::hypot(uv.x() - pb.x, uv.y() - pb.y);
  }
  return errors;
}

}  // namespace icgm
