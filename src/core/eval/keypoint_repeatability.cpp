#include "core/eval/keypoint_repeatability.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>

namespace icgm {
namespace {

float DepthAt(const cv::Mat& depth_m, double u, double v) {
  const int x = static_cast<int>(std::lround(u));
  const int y = static_cast<int>(std::lround(v));
  if (x < 0 || y < 0 || x >= depth_m.cols || y >= depth_m.rows) return 0.0f;
  const float z = depth_m.at<float>(y, x);
  return z > 0.0f ? z : 0.0f;  // NaN -> 0
}

bool Moving(const cv::Mat& mask, double u, double v) {
  if (mask.empty()) return false;
  const int x = std::clamp(static_cast<int>(std::lround(u)), 0, mask.cols - 1);
  const int y = std::clamp(static_cast<int>(std::lround(v)), 0, mask.rows - 1);
  return mask.at<uint8_t>(y, x) != 0;
}

double Median(std::vector<double> v) {
  if (v.empty()) return 0.0;
  const size_t k = v.size() / 2;
  std::nth_element(v.begin(), v.begin() + k, v.end());
  return v[k];
}

}  // namespace

KeypointRepeatabilityStats MeasureKeypointRepeatability(
    const std::vector<cv::KeyPoint>& a, const cv::Mat& depth_a_m, const cv::Mat& mask_a,
    const std::vector<cv::KeyPoint>& b, const cv::Mat& depth_b_m, const cv::Mat& mask_b,
    const std::vector<cv::DMatch>& matches, const CameraIntrinsics& intrinsics,
    const Pose3& b_from_a, const KeypointRepeatabilityOptions& options) {
  KeypointRepeatabilityStats s;
  if (depth_a_m.type() != CV_32FC1 || depth_b_m.type() != CV_32FC1) return s;
  // The true reprojection of every room keypoint of a that b sees.
  std::vector<std::optional<Eigen::Vector2d>> room(a.size());
  const double w = depth_b_m.cols, h = depth_b_m.rows, border = options.border_px;
  for (size_t i = 0; i < a.size(); ++i) {
    const cv::Point2f p = a[i].pt;
    const float z = DepthAt(depth_a_m, p.x, p.y);
    if (z <= 0.0f || z < options.min_depth_m || Moving(mask_a, p.x, p.y)) continue;
    const Eigen::Vector3d in_b = b_from_a * intrinsics.BackProject(p.x, p.y, z);
    if (in_b.z() <= 1e-6) continue;
    const Eigen::Vector2d uv = intrinsics.Project(in_b);
    if (uv.x() < border || uv.y() < border || uv.x() > w - 1 - border || uv.y() > h - 1 - border) {
      continue;
    }
    const float zb = DepthAt(depth_b_m, uv.x(), uv.y());
    if (zb <= 0.0f || std::abs(zb - in_b.z()) > options.visible_depth_fraction * in_b.z()) continue;
    if (Moving(mask_b, uv.x(), uv.y())) continue;
    room[i] = uv;
    ++s.room_keypoints;
  }
  const auto offset = [&](const cv::DMatch& m) -> std::optional<Eigen::Vector2d> {
    if (m.queryIdx < 0 || m.queryIdx >= static_cast<int>(a.size()) || m.trainIdx < 0 ||
        m.trainIdx >= static_cast<int>(b.size()) || !room[m.queryIdx]) {
      return std::nullopt;
    }
    const cv::Point2f pb = b[m.trainIdx].pt;
    return Eigen::Vector2d(pb.x, pb.y) - *room[m.queryIdx];
  };
  std::vector<double> dx, dy;
  for (const cv::DMatch& m : matches) {
    const auto d = offset(m);
    if (d && d->norm() <= options.shift_search_px) dx.push_back(d->x()), dy.push_back(d->y());
  }
  s.shift_support = static_cast<int>(dx.size());
  s.common_shift_px = Eigen::Vector2d(Median(dx), Median(dy));
  for (size_t i = 0; i < a.size(); ++i) {
    if (!room[i]) continue;
    const Eigen::Vector2d target = *room[i] + s.common_shift_px;
    double nearest = std::numeric_limits<double>::infinity();
    for (const cv::KeyPoint& k : b) {
      nearest = std::min(nearest, std::hypot(k.pt.x - target.x(), k.pt.y - target.y()));
    }
    s.repeated_1px += nearest <= 1.0;
    s.repeated_2px += nearest <= 2.0;
  }
  for (const cv::DMatch& m : matches) {
    const auto d = offset(m);
    if (!d) continue;
    ++s.matched;
    const double corrected = (*d - s.common_shift_px).norm();
    if (corrected > options.correct_px) continue;
    ++s.matched_correct;
    s.correct_errors_px.push_back(corrected);
    s.raw_errors_px.push_back(d->norm());
  }
  return s;
}

}  // namespace icgm
