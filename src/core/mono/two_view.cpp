#include "core/mono/two_view.h"

#include <algorithm>
#include <string>

#include <opencv2/calib3d.hpp>
#include <opencv2/core/eigen.hpp>

#include "core/mono/ransac_order.h"
#include "core/optimization/bundle_adjustment.h"

namespace icgm {

namespace {
// Two-view bundle adjustment of the RANSAC motion over its inliers (camera a fixed), then the
// baseline scaled back to length 1: the minimal-sample essential matrix carries the noise of
// five matches only.
void Refine(const std::vector<Eigen::Vector2d>& pixels_a,
            const std::vector<Eigen::Vector2d>& pixels_b, const CameraIntrinsics& intrinsics,
            const TwoViewOptions& options, TwoViewResult* out) {
  TriangulationCheck loose = options.triangulation;
  loose.min_angle_deg = 0.0;
  loose.max_depth_baselines = 0.0;
  loose.max_reprojection_px = 4.0 * options.ransac_threshold_px + 1.0;
  BaProblem problem;
  problem.world_camera = {Pose3::Identity(), out->a_b};
  problem.fixed = {1, 0};
  std::vector<size_t> match_of;
  for (size_t i = 0; i < pixels_a.size(); ++i) {
    if (!out->inliers[i]) continue;
    const TriangulatedPoint p =
        TriangulatePoint(intrinsics, Pose3::Identity(), pixels_a[i], out->a_b, pixels_b[i], loose);
    if (!p.status.ok()) continue;
    const int point = static_cast<int>(problem.points_world.size());
    problem.points_world.push_back(p.point_world);
    for (int c = 0; c < 2; ++c) {
      BaObservation obs;
      obs.camera = c;
      obs.point = point;
      obs.pixel_px = c == 0 ? pixels_a[i] : pixels_b[i];
      problem.observations.push_back(obs);
    }
    match_of.push_back(i);
  }
  if (match_of.size() < 8) return;
  BundleAdjustmentOptions ba;
  ba.use_depth = false;
  ba.max_iterations = options.refine_max_iterations;
  ba.max_solver_time_s = options.refine_max_solver_time_s;
  ba.outlier_rounds = 0;
  ba.huber_sigma = 2.0 * options.ransac_threshold_px;
  if (!BundleAdjust(intrinsics, ba, &problem).ok()) return;
  const double length = problem.world_camera[1].translation().norm();
  if (!(length > 1e-9) || !problem.world_camera[1].matrix().allFinite()) return;
  out->a_b = problem.world_camera[1];
  out->a_b.translation() /= length;
}
}  // namespace

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
  // RANSAC's input in the order drawn from ransac_order_seed (input order for 0).
  const std::vector<size_t> order = RansacOrder(n, options.ransac_order_seed);
  std::vector<cv::Point2d> a(n), b(n);
  for (size_t k = 0; k < n; ++k) {
    a[k] = cv::Point2d(pixels_a[order[k]].x(), pixels_a[order[k]].y());
    b[k] = cv::Point2d(pixels_b[order[k]].x(), pixels_b[order[k]].y());
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
  std::vector<uint8_t> drawn(n, 0);
  for (size_t i = 0; i < n; ++i) drawn[i] = mask.at<uint8_t>(static_cast<int>(i)) ? 1 : 0;
  out.inliers = FlagsInInputOrder(drawn, order);
  out.num_inliers = static_cast<size_t>(std::count(out.inliers.begin(), out.inliers.end(), 1));
  if (options.refine) Refine(pixels_a, pixels_b, intrinsics, options, &out);
  std::vector<double> angles;
  for (size_t i = 0; i < n; ++i) {
    if (!out.inliers[i]) continue;
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
