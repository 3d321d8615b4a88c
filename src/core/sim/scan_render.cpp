#include "core/sim/scan_render.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>

namespace icgm::sim {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

// Entry distance of the ray into the axis-aligned rectangle [lo, hi] (slab method); 0 when the
// origin is inside, infinity when it misses.
double RayRectangle(const Eigen::Vector2d& o, const Eigen::Vector2d& d, const Eigen::Vector2d& lo,
                    const Eigen::Vector2d& hi) {
  double t0 = 0.0, t1 = kInf;
  for (int k = 0; k < 2; ++k) {
    if (std::abs(d[k]) < 1e-12) {
      if (o[k] < lo[k] || o[k] > hi[k]) return kInf;
      continue;
    }
    double a = (lo[k] - o[k]) / d[k], b = (hi[k] - o[k]) / d[k];
    if (a > b) std::swap(a, b);
    t0 = std::max(t0, a);
    t1 = std::min(t1, b);
    if (t0 > t1) return kInf;
  }
  return t0;
}

// Distance to the circle of radius r around c (0 inside), infinity when missed.
double RayCircle(const Eigen::Vector2d& o, const Eigen::Vector2d& d, const Eigen::Vector2d& c,
                 double r) {
  const Eigen::Vector2d m = o - c;
  const double b = m.dot(d), cc = m.squaredNorm() - r * r;
  if (cc <= 0.0) return 0.0;
  const double disc = b * b - cc;
  if (b > 0.0 || disc < 0.0) return kInf;
  return -b - std::sqrt(disc);
}

// Exit distance from inside the room [0, W] x [0, L].
double RayRoom(const Eigen::Vector2d& o, const Eigen::Vector2d& d, const Room& room) {
  double t = kInf;
  const double hi[2] = {room.width_m, room.length_m};
  for (int k = 0; k < 2; ++k) {
    if (d[k] > 1e-12) t = std::min(t, (hi[k] - o[k]) / d[k]);
    if (d[k] < -1e-12) t = std::min(t, -o[k] / d[k]);
  }
  return std::max(0.0, t);
}

}  // namespace

Pose3 ScannerMountPose(const ScannerOptions& options) {
  Pose3 T = Pose3::Identity();
  T.translation() = Eigen::Vector3d(options.forward_m, 0.0, options.height_m);
  return T;
}

double CastPlanarRay(const StaticScene& scene, const std::vector<CylinderPrimitive>& cylinders,
                     const Eigen::Vector2d& origin, const Eigen::Vector2d& dir, double height_m) {
  double t = RayRoom(origin, dir, scene.room);
  for (const BoxPrimitive& b : scene.boxes) {
    if (height_m < b.min_m.z() || height_m > b.max_m.z()) continue;
    t = std::min(t, RayRectangle(origin, dir, b.min_m.head<2>().cast<double>(),
                                 b.max_m.head<2>().cast<double>()));
  }
  for (const CylinderPrimitive& c : cylinders) {
    if (height_m < c.z_min_m || height_m > c.z_max_m) continue;
    t = std::min(t, RayCircle(origin, dir, Eigen::Vector2d(c.x_m, c.y_m), c.radius_m));
  }
  return t;
}

PlanarScan RenderPlanarScan(const ScannerOptions& options, const StaticScene& scene,
                            const std::vector<CylinderPrimitive>& cylinders, const PlanarPose& base,
                            Time stamp, Rng& rng) {
  PlanarScan scan;
  scan.stamp = stamp;
  const double fov = options.fov_deg * M_PI / 180.0;
  const bool full_circle = options.fov_deg >= 360.0;
  scan.angle_min_rad = -0.5 * fov;
  scan.angle_increment_rad = fov / (full_circle ? options.beams : options.beams - 1);
  scan.range_min_m = options.min_range_m;
  scan.range_max_m = options.max_range_m;
  scan.ranges_m.resize(static_cast<size_t>(options.beams));
  const Eigen::Vector2d origin(base.x_m + options.forward_m * std::cos(base.yaw_rad),
                               base.y_m + options.forward_m * std::sin(base.yaw_rad));
  std::normal_distribution<double> noise(0.0, options.range_noise_m);
  for (size_t i = 0; i < scan.ranges_m.size(); ++i) {
    const double a = base.yaw_rad + scan.BeamAngle(i);
    const Eigen::Vector2d dir(std::cos(a), std::sin(a));
    double r = CastPlanarRay(scene, cylinders, origin, dir, options.height_m);
    if (options.range_noise_m > 0.0) r += noise(rng);  // drawn for every beam: a fixed stream
    scan.ranges_m[i] = r <= options.max_range_m ? static_cast<float>(r)
                                                 : std::numeric_limits<float>::infinity();
  }
  return scan;
}

}  // namespace icgm::sim
