#include "core/odometry/local_map.h"

#include <algorithm>
#include <cmath>
#include <sstream>

#include <Eigen/Dense>

#include "core/odometry/keypoint_grid.h"
#include "core/registration/pose_refinement.h"

namespace icgm {

void AddKeyframePoints(const cv::Mat& descriptors, bool binary,
                       const std::vector<Eigen::Vector3d>& points_camera,
                       const std::vector<uint8_t>& use, const Pose3& odom_camera,
                       LocalMapPoints* map) {
  if (descriptors.empty() || descriptors.rows != static_cast<int>(points_camera.size())) return;
  if (map->descriptors.empty()) map->binary = binary;
  if (map->binary != binary ||
      (!map->descriptors.empty() && (map->descriptors.cols != descriptors.cols ||
                                     map->descriptors.type() != descriptors.type()))) {
    return;
  }
  for (size_t i = 0; i < points_camera.size(); ++i) {
    if ((!use.empty() && !use[i]) || !points_camera[i].allFinite()) continue;
    map->odom_points.push_back(odom_camera * points_camera[i]);
    map->descriptors.push_back(descriptors.row(static_cast<int>(i)));
  }
}

namespace {

struct Match {
  int point = 0;
  int keypoint = 0;
};

}  // namespace

LocalMapTrackResult TrackLocalMap(const LocalMapPoints& map,
                                  const std::vector<cv::KeyPoint>& keypoints,
                                  const cv::Mat& descriptors,
                                  const std::vector<double>& pixel_sigma_px,
                                  const std::vector<uint8_t>& usable, const cv::Mat& depth_m,
                                  const Pose3& start, const CameraIntrinsics& intrinsics,
                                  const LocalMapOptions& options) {
  const bool check_depth = !depth_m.empty() && depth_m.type() == CV_32FC1;
  LocalMapTrackResult result;
  result.odom_camera = start;
  if (map.size() == 0 || keypoints.empty() ||
      descriptors.rows != static_cast<int>(keypoints.size()) ||
      pixel_sigma_px.size() != keypoints.size() || descriptors.type() != map.descriptors.type() ||
      descriptors.cols != map.descriptors.cols) {
    result.status = Status::Error("local map: no map points or no usable current features");
    return result;
  }
  const int norm = map.binary ? cv::NORM_HAMMING : cv::NORM_L2;
  std::vector<cv::Point2f> positions_px(keypoints.size());
  for (size_t i = 0; i < keypoints.size(); ++i) positions_px[i] = keypoints[i].pt;
  const KeypointGrid grid(std::move(positions_px), usable, options.search_px);
  Pose3 odom_cam = start;
  double radius = options.search_px;
  std::vector<Match> matches;
  for (int round = 0; round < std::max(1, options.rounds); ++round) {
    // 1. Matching: each map point to the nearest descriptor within the radius of its
    // projection; each keypoint keeps its best map point.
    const Pose3 cam_odom = odom_cam.inverse();
    std::vector<int> best_point(keypoints.size(), -1);
    std::vector<double> best_distance(keypoints.size(), INFINITY);
    for (size_t p = 0; p < map.size(); ++p) {
      const Eigen::Vector3d pc = cam_odom * map.odom_points[p];
      if (pc.z() < 0.1) continue;
      const Eigen::Vector2d u = intrinsics.Project(pc);
      if (u.x() < 0 || u.y() < 0 || u.x() >= intrinsics.width_px || u.y() >= intrinsics.height_px) {
        continue;
      }
      int best = -1;
      double best_d = options.max_descriptor_distance;
      const double tolerance_m = options.depth_abs_m + options.depth_rel_per_m * pc.z() * pc.z();
      grid.ForEachNear(u, radius, [&](int k) {
        if (check_depth) {
          const cv::Point2f& q = keypoints[k].pt;
          const float z = depth_m.at<float>(std::min(depth_m.rows - 1, std::max(0, cvRound(q.y))),
                                            std::min(depth_m.cols - 1, std::max(0, cvRound(q.x))));
          if (std::isfinite(z) && z > 0.0f && std::abs(z - pc.z()) > tolerance_m) return;
        }
        const double d =
            cv::norm(map.descriptors.row(static_cast<int>(p)), descriptors.row(k), norm);
        if (d <= best_d) {
          best_d = d;
          best = k;
        }
      });
      if (best >= 0 && best_d < best_distance[best]) {
        best_distance[best] = best_d;
        best_point[best] = static_cast<int>(p);
      }
    }
    matches.clear();
    for (size_t k = 0; k < keypoints.size(); ++k) {
      if (best_point[k] >= 0) matches.push_back({best_point[k], static_cast<int>(k)});
    }
    if (static_cast<int>(matches.size()) < options.min_matches) {
      std::ostringstream s;
      s << "local map: " << matches.size() << " matches < " << options.min_matches;
      result.status = Status::Error(s.str());
      result.matches = matches.size();
      return result;
    }
    // 2. Gauss-Newton on the Huber reprojection error, T_odom_cam <- T_odom_cam * Exp(eps).
    double sum_sq = 0.0;
    Mat6 h = Mat6::Zero();
    for (int it = 0; it < std::max(1, options.iterations); ++it) {
      const Pose3 c_o = odom_cam.inverse();
      h.setZero();
      Vec6 g = Vec6::Zero();
      sum_sq = 0.0;
      for (const Match& m : matches) {
        const Eigen::Vector3d pc = c_o * map.odom_points[m.point];
        if (pc.z() < 0.1) continue;
        const double s = pixel_sigma_px[m.keypoint];
        const Eigen::Vector2d u = intrinsics.Project(pc);
        const Eigen::Vector2d r =
            (u - Eigen::Vector2d(keypoints[m.keypoint].pt.x, keypoints[m.keypoint].pt.y)) / s;
        const double n = r.norm();
        const double w = n <= options.huber_px ? 1.0 : options.huber_px / n;
        sum_sq += r.squaredNorm();
        // p_c(eps) = Exp(eps)^-1 p_c ~ p_c - t - w x p_c: dp/dt = -I, dp/dw = [p_c]x.
        Eigen::Matrix<double, 3, 6> dp;
        dp << -Eigen::Matrix3d::Identity(), Skew(pc);
        const Eigen::Matrix<double, 2, 6> j = ProjectionJacobian(pc, intrinsics) * dp / s;
        h += w * j.transpose() * j;
        g += w * j.transpose() * r;
      }
      const Vec6 step = h.ldlt().solve(-g);
      if (!step.allFinite()) {
        result.status = Status::Error("local map: degenerate system");
        return result;
      }
      odom_cam = Orthonormalized(odom_cam * ExpSE3(step));
      if (step.head<3>().norm() + step.tail<3>().norm() < 1e-7) break;
    }
    result.matches = matches.size();
    result.rms_px = std::sqrt(sum_sq / matches.size());
    const double variance = sum_sq / std::max<double>(1.0, 2.0 * matches.size() - 6.0);
    result.covariance = variance * h.ldlt().solve(Mat6::Identity());
    radius = std::max(2.0 * options.huber_px, radius / 2.0);
  }
  const Pose3 d = start.inverse() * odom_cam;
  const double moved_deg = Eigen::AngleAxisd(d.rotation()).angle() * 180.0 / M_PI;
  if (d.translation().norm() > options.max_correction_m || moved_deg > options.max_correction_deg) {
    std::ostringstream s;
    s << "local map: correction " << d.translation().norm() << " m, " << moved_deg
      << " deg beyond the bound";
    result.status = Status::Error(s.str());
    return result;
  }
  result.odom_camera = odom_cam;
  return result;
}

}  // namespace icgm
