#include "core/mono/rotation_only.h"

#include <algorithm>
#include <cmath>
#include <random>
#include <string>

#include <Eigen/SVD>

namespace icgm {

namespace {

constexpr double kRadToDeg = 180.0 / M_PI;

// The rotation R minimizing sum |b_k - R a_k|^2 (Kabsch): from the SVD of sum b_k a_k^T, the
// sign of the last singular direction chosen so that det R = +1.
Eigen::Matrix3d FitRotation(const std::vector<Eigen::Vector3d>& a,
                            const std::vector<Eigen::Vector3d>& b, const std::vector<int>& use) {
  Eigen::Matrix3d h = Eigen::Matrix3d::Zero();
  for (const int k : use) h += b[k] * a[k].transpose();
  const Eigen::JacobiSVD<Eigen::Matrix3d> svd(h, Eigen::ComputeFullU | Eigen::ComputeFullV);
  Eigen::Matrix3d d = Eigen::Matrix3d::Identity();
  d(2, 2) = (svd.matrixU() * svd.matrixV().transpose()).determinant() < 0.0 ? -1.0 : 1.0;
  return svd.matrixU() * d * svd.matrixV().transpose();
}

double AngleRad(const Eigen::Vector3d& u, const Eigen::Vector3d& v) {
  return std::atan2(u.cross(v).norm(), u.dot(v));
}

}  // namespace

Eigen::Vector3d PixelBearing(const CameraIntrinsics& intrinsics, const Eigen::Vector2d& px) {
  return intrinsics.BackProject(px.x(), px.y(), 1.0).normalized();
}

RotationOnlyResult EstimateRotationOnly(const std::vector<Eigen::Vector2d>& pixels_a,
                                        const std::vector<Eigen::Vector2d>& pixels_b,
                                        const CameraIntrinsics& intrinsics,
                                        const RotationOnlyOptions& options) {
  RotationOnlyResult r;
  const size_t n = std::min(pixels_a.size(), pixels_b.size());
  r.inliers.assign(n, 0);
  if (n < 2 || static_cast<int>(n) < options.min_inliers) {
    r.status = Status::Error("rotation only: " + std::to_string(n) + " matches < " +
                             std::to_string(std::max(2, options.min_inliers)));
    return r;
  }
  std::vector<Eigen::Vector3d> a(n), b(n);
  for (size_t k = 0; k < n; ++k) {
    a[k] = PixelBearing(intrinsics, pixels_a[k]);
    b[k] = PixelBearing(intrinsics, pixels_b[k]);
  }
  const double threshold = options.inlier_px / std::max(1e-9, intrinsics.fx_px);
  const auto inliers_of = [&](const Eigen::Matrix3d& rot, std::vector<int>* in) {
    in->clear();
    for (size_t k = 0; k < n; ++k) {
      if (AngleRad(rot * a[k], b[k]) <= threshold) in->push_back(static_cast<int>(k));
    }
  };
  std::mt19937 rng(options.rng_seed);
  std::uniform_int_distribution<int> pick(0, static_cast<int>(n) - 1);
  std::vector<int> best, in;
  Eigen::Matrix3d best_rot = Eigen::Matrix3d::Identity();
  for (int it = 0; it < options.iterations; ++it) {
    const int i = pick(rng);
    const int j = pick(rng);
    // Two bearings too close together leave the rotation about them free.
    if (i == j || AngleRad(a[i], a[j]) < 2.0 * threshold) continue;
    const Eigen::Matrix3d rot = FitRotation(a, b, {i, j});
    inliers_of(rot, &in);
    if (in.size() > best.size()) {
      best.swap(in);
      best_rot = rot;
    }
  }
  // Refit on the inliers, once more on the refit's inliers.
  for (int round = 0; round < 2 && best.size() >= 2; ++round) {
    const Eigen::Matrix3d rot = FitRotation(a, b, best);
    inliers_of(rot, &in);
    if (in.size() < best.size()) break;
    best.swap(in);
    best_rot = rot;
  }
  r.b_R_a = best_rot;
  r.num_inliers = best.size();
  for (const int k : best) r.inliers[k] = 1;
  r.median_parallax_deg = MedianParallaxDeg(best_rot, pixels_a, pixels_b, intrinsics, r.inliers);
  if (static_cast<int>(best.size()) < options.min_inliers) {
    r.status = Status::Error("rotation only: " + std::to_string(best.size()) + " inliers < " +
                             std::to_string(options.min_inliers));
  }
  return r;
}

double MedianParallaxDeg(const Eigen::Matrix3d& b_R_a, const std::vector<Eigen::Vector2d>& pixels_a,
                         const std::vector<Eigen::Vector2d>& pixels_b,
                         const CameraIntrinsics& intrinsics, const std::vector<uint8_t>& use) {
  std::vector<double> angles;
  const size_t n = std::min(pixels_a.size(), pixels_b.size());
  for (size_t k = 0; k < n; ++k) {
    if (!use.empty() && (k >= use.size() || !use[k])) continue;
    angles.push_back(AngleRad(b_R_a * PixelBearing(intrinsics, pixels_a[k]),
                              PixelBearing(intrinsics, pixels_b[k])) *
                     kRadToDeg);
  }
  if (angles.empty()) return 0.0;
  std::nth_element(angles.begin(), angles.begin() + angles.size() / 2, angles.end());
  return angles[angles.size() / 2];
}

}  // namespace icgm
