// The motion of a camera held in the hand of a person standing (or walking) in a room
// (camera_motion: handheld): a walk along the viewing direction, a slow drift of the position,
// slow panning, tilting and rolling, and hand shake, each a sum of sinusoids with random
// frequencies and phases. Poses are a smooth, exact function of time, so the simulator can
// evaluate them inside an exposure as well as at the stamps.
#pragma once

#include <vector>

#include "core/common/pose.h"
#include "core/dataset/trajectory.h"
#include "core/sim/loop_route.h"
#include "core/sim/sim_options.h"
#include "core/sim/texture_drawing.h"

namespace icgm::sim {

class HandheldMotion {
 public:
  HandheldMotion() = default;
  // Draws the motion for a sequence of duration_s seconds; the drift's amplitudes are scaled so
  // that the mean speed over the sequence is options.drift_speed_mps. With
  // options.recorded_trajectory, replays that recording instead (throws LoadError when it cannot
  // be read, has fewer than two poses or starts after its end).
  HandheldMotion(const HandheldOptions& options, double duration_s, Rng& rng);

  // camera_rgb_optical_frame in the world at t_s seconds after the first frame.
  Pose3 T_world_camera(double t_s) const;
  // The camera's position on the floor plan and its horizontal viewing direction.
  PlanarPose ViewOnFloor(double t_s) const;

 private:
  struct Wave {
    double amplitude = 0.0;
    double omega_rad_per_s = 0.0;
    double phase_rad = 0.0;
  };
  // `count` waves with periods uniform in [min_period_s, max_period_s], random phases and
  // amplitudes summing to `amplitude`.
  static std::vector<Wave> DrawWaves(Rng& rng, int count, double amplitude, double min_period_s,
                                     double max_period_s);
  static double Sum(const std::vector<Wave>& waves, double t_s);

  // The walk's displacement from the start at t_s (HandheldOptions::walk_speed_mps; zero when
  // standing).
  Eigen::Vector3d Walk(double t_s) const;

  // The recording's pose recorded_start_s after its first stamp + t_s (held at its last pose).
  Pose3 Recorded(double t_s) const;

  HandheldOptions options_;
  Trajectory recorded_;  // empty: the random motion
  Pose3 recorded_start_inverse_ = Pose3::Identity();
  // Position drift (x, y, z) relative to the start, then shake; angles in radians.
  std::vector<Wave> drift_[3], shake_[3];
  std::vector<Wave> pan_, tilt_, roll_, shake_angle_[3];
  double drift_scale_ = 1.0;
};

}  // namespace icgm::sim
