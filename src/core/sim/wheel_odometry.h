// Wheel odometry of a differential-drive base: integrates the true planar motion between frames
// with a distance scale error, a heading bias per metre and random drift whose variance grows
// linearly with the distance driven (OdometryNoiseOptions).
#pragma once

#include <vector>

#include <Eigen/Core>

#include "core/common/pose.h"
#include "core/sim/loop_route.h"
#include "core/sim/procedural_textures.h"
#include "core/sim/sim_options.h"

namespace icgm::sim {

struct OdometrySample {
  // Pose of base_link in the odom frame; odom coincides with base_link at the first frame.
  Pose3 T_odom_base = Pose3::Identity();
  // Velocities in base_link as measured by the wheels (x forward, rotation about z).
  Eigen::Vector3d linear_velocity_mps = Eigen::Vector3d::Zero();
  Eigen::Vector3d angular_velocity_rps = Eigen::Vector3d::Zero();
};

// Integrates wheel odometry one step of true motion at a time (the model SimulateWheelOdometry
// applies to a whole path).
class WheelOdometryIntegrator {
 public:
  explicit WheelOdometryIntegrator(const OdometryNoiseOptions& options) : options_(options) {}
  // Adds the true motion from `from` to `to`, dt_s > 0 apart, as the wheels measure it.
  const OdometrySample& Step(const PlanarPose& from, const PlanarPose& to, double dt_s, Rng& rng);
  const OdometrySample& sample() const { return sample_; }

 private:
  OdometryNoiseOptions options_;
  double x_ = 0.0, y_ = 0.0, yaw_ = 0.0;
  OdometrySample sample_;
};

// One sample per true pose; truth[i] and truth[i + 1] are dt_s apart.
std::vector<OdometrySample> SimulateWheelOdometry(const std::vector<PlanarPose>& truth, double dt_s,
                                                  const OdometryNoiseOptions& options, Rng& rng);

// Planar pose -> base_link pose (on the floor, z = 0).
Pose3 ToPose3(const PlanarPose& p);

}  // namespace icgm::sim
