// Test helper: random points in a box in front of camera a, seen from a and from b (T_a_b known),
// with pixel noise and a share of matches replaced by random pixels (outliers).
#pragma once

#include <cstdint>
#include <random>
#include <vector>

#include "core/common/camera.h"
#include "core/common/pose.h"

namespace icgm::test {

struct TwoViewScene {
  std::vector<Eigen::Vector3d> points_a;  // in camera a
  std::vector<Eigen::Vector2d> pixels_a, pixels_b;
  std::vector<bool> outlier;
};

// The points' box in camera a: x within +-half_x_m, y within +-half_y_m, z within
// near_z_m + [0, 2 half_z_m]; `count` points visible in both views.
struct SceneBox {
  double half_x_m = 2.0, half_y_m = 1.5, near_z_m = 2.0, half_z_m = 1.0;
  size_t count = 200;
};

inline TwoViewScene MakeTwoViewScene(const CameraIntrinsics& k, const Pose3& a_b,
                                     double noise_px, double outliers, uint32_t seed,
                                     const SceneBox& box) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-1.0, 1.0), unit(0.0, 1.0);
  std::normal_distribution<double> noise(0.0, noise_px);
  TwoViewScene s;
  const Pose3 b_a = a_b.inverse();
  const auto inside = [&](const Eigen::Vector2d& x) {
    return x.x() >= 0 && x.y() >= 0 && x.x() < k.width_px && x.y() < k.height_px;
  };
  while (s.pixels_a.size() < box.count) {
    const Eigen::Vector3d p(box.half_x_m * u(rng), box.half_y_m * u(rng),
                            box.near_z_m + box.half_z_m * (1.0 + u(rng)));
    const Eigen::Vector3d pb = b_a * p;
    const Eigen::Vector2d xa = k.Project(p), xb = k.Project(pb);
    if (pb.z() <= 0.1 || !inside(xa) || !inside(xb)) continue;
    const bool bad = unit(rng) < outliers;
    s.points_a.push_back(p);
    s.pixels_a.push_back(xa + Eigen::Vector2d(noise(rng), noise(rng)));
    s.pixels_b.push_back(bad ? Eigen::Vector2d(k.width_px * unit(rng), k.height_px * unit(rng))
                             : Eigen::Vector2d(xb + Eigen::Vector2d(noise(rng), noise(rng))));
    s.outlier.push_back(bad);
  }
  return s;
}

}  // namespace icgm::test
