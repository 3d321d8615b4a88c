#include "core/mono/two_view.h"

#include <algorithm>
#include <string>

#include <opencv2/calib3d.hpp>
#include <opencv2/core/eigen.hpp>

namespace icgm {

TwoViewResult RecoverTwoViewMotion(const std::vector<Eigen::Vector2d>& pixels_a,
                                   const std::vector<Eigen::Vector2d>& pixels_b,
                                   const CameraIntrinsics& intrinsics,
                                   const TwoViewOptions& options) {
  TwoViewResult out;
  const size_t n = pixels_a.size();
  out.inliers.assign(n, 0);
  out.triangulated.assign(n, 0);
  out.points_a.assign(n, Eigen::Vector3d::Zero());
  if (pixels_b.size() != n) {
    out.status = Status::Error("match lists of different sizes");
    return out;
  }
  if (n < 5) {
    out.status = Status::Error(std::to_string(n) + " matches < 5 for the essential matrix");
    return out;
  }
  std::vector<cv::Point2d> a(n), b(n);
  for (size_t k = 0; k < n; ++k) {
    a[k] = cv::Point2d(pixels_a[k].x(), pixels_a[k].y());
    b[k] = cv::Point2d(pixels_b[k].x(), pixels_b[k].y());
  }
  const cv::Matx33d k(intrinsics.fx_px, 0, intrinsics.cx_px, 0, intrinsics.fy_px, intrinsics.cy_px,
                      0, 0, 1);
  cv::Mat mask;
  cv::Mat e;
  try {
    e = cv::findEssentialMat(a, b, k, cv::RANSAC, options.ransac_confidence,
                             options.ransac_threshold_px, mask);
  } catch (const cv::Exception& ex) {
    out.status = Status::Error(std::string("essential matrix failed: ") + ex.what());
    return out;
  }
  if (e.rows != 3 || e.cols != 3) {
    // Several solutions stacked (3k x 3) or none: the configuration is degenerate.
    out.status = Status::Error("no unique essential matrix");
    return out;
  }
  cv::Mat r, t;
  int good = 0;
  try {
    good = cv::recoverPose(e, a, b, k, r, t, mask);
  } catch (const cv::Exception& ex) {
    out.status = Status::Error(std::string("pose recovery failed: ") + ex.what());
    return out;
  }
  if (good < 5) {
    out.status = Status::Error(std::to_string(good) + " matches pass the cheirality test");
    return out;
  }
  // recoverPose gives x_b = R x_a + t, i.e. T_b_a.
  Eigen::Matrix3d rb;
  Eigen::Vector3d tb;
  cv::cv2eigen(r, rb);
  cv::cv2eigen(t, tb);
  Pose3 b_a = Pose3::Identity();
  b_a.linear() = rb;
  b_a.translation() = tb.normalized();
  out.a_b = b_a.inverse();
  std::vector<double> angles;
  for (size_t i = 0; i < n; ++i) {
    if (!mask.at<uint8_t>(static_cast<int>(i))) continue;
    out.inliers[i] = 1;
    ++out.num_inliers;
    const TriangulatedPoint p = TriangulatePoint(intrinsics, Pose3::Identity(), pixels_a[i],
                                                 out.a_b, pixels_b[i], options.triangulation);
    if (!p.status.ok()) continue;
    out.triangulated[i] = 1;
    out.points_a[i] = p.point_world;
    ++out.num_triangulated;
    angles.push_back(p.angle_deg);
  }
  if (!angles.empty()) {
    std::nth_element(angles.begin(), angles.begin() + angles.size() / 2, angles.end());
    out.median_parallax_deg = angles[angles.size() / 2];
  }
  return out;
}

}  // namespace icgm
