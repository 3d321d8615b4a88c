#include "core/sim/wheel_odometry.h"

#include <cmath>

namespace icgm::sim {

Pose3 ToPose3(const PlanarPose& p) {
  Pose3 T = Pose3::Identity();
  T.linear() = Eigen::AngleAxisd(p.yaw_rad, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  T.translation() = Eigen::Vector3d(p.x_m, p.y_m, 0.0);
  return T;
}

const OdometrySample& WheelOdometryIntegrator::Step(const PlanarPose& a, const PlanarPose& b,
                                                    double dt_s, Rng& rng) {
  const OdometryNoiseOptions& o = options_;
  std::normal_distribution<double> normal(0.0, 1.0);
  // True increment in the previous base frame.
  const double c = std::cos(a.yaw_rad), s = std::sin(a.yaw_rad);
  const double dx_w = b.x_m - a.x_m, dy_w = b.y_m - a.y_m;
  const double dx = c * dx_w + s * dy_w, dy = -s * dx_w + c * dy_w;
  const double dyaw = std::remainder(b.yaw_rad - a.yaw_rad, 2 * M_PI);
  const double dist = std::hypot(dx, dy);
  // Measured increment: scaled distance, biased heading, noise ~ sqrt(distance).
  const double noisy_dist =
      dist * (1.0 + o.scale_error) + o.distance_noise_m_per_sqrt_m * std::sqrt(dist) * normal(rng);
  const double noisy_dyaw = dyaw + o.heading_bias_rad_per_m * dist +
                            o.heading_noise_rad_per_sqrt_m * std::sqrt(dist) * normal(rng);
  const double k = dist > 1e-12 ? noisy_dist / dist : 0.0;
  // Integrate at the mid-heading of the step (exact for constant-curvature arcs in the limit).
  const double half = yaw_ + 0.5 * (noisy_dyaw - dyaw);
  const double mx = k * dx, my = k * dy;
  x_ += std::cos(half) * mx - std::sin(half) * my;
  y_ += std::sin(half) * mx + std::cos(half) * my;
  yaw_ = std::remainder(yaw_ + noisy_dyaw, 2 * M_PI);
  sample_.T_odom_base = ToPose3({x_, y_, yaw_});
  sample_.linear_velocity_mps = Eigen::Vector3d(k * dx / dt_s, k * dy / dt_s, 0.0);
  sample_.angular_velocity_rps = Eigen::Vector3d(0.0, 0.0, noisy_dyaw / dt_s);
  return sample_;
}

std::vector<OdometrySample> SimulateWheelOdometry(const std::vector<PlanarPose>& truth, double dt_s,
                                                  const OdometryNoiseOptions& o, Rng& rng) {
  std::vector<OdometrySample> out(truth.size());
  WheelOdometryIntegrator odometry(o);
  for (size_t i = 1; i < truth.size(); ++i) {
    out[i] = odometry.Step(truth[i - 1], truth[i], dt_s, rng);
  }
  return out;
}

}  // namespace icgm::sim
