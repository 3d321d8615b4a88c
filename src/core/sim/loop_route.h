// The robot's route: a counter-clockwise rounded rectangle inset from the room's walls, driven
// with a trapezoidal speed profile (accelerate from rest, cruise, brake to rest at the end).
#pragma once

#include <Eigen/Core>

#include "core/sim/sim_options.h"

namespace icgm::sim {

// Planar pose of base_link in the world: position on the floor and heading (yaw) in radians.
struct PlanarPose {
  double x_m = 0.0;
  double y_m = 0.0;
  double yaw_rad = 0.0;
};

class LoopRoute {
 public:
  LoopRoute(const RoomOptions& room, const RouteOptions& route);

  double length_m() const { return length_m_; }
  // Pose at arc length s_m from the start point (the middle of the south side, heading +x,
  // shifted by route.start_offset_m); wraps around the loop.
  PlanarPose PoseAt(double s_m) const;
  // Distance from (x, y) to the loop curve.
  double DistanceTo(double x_m, double y_m) const;

  // Arc length driven after t_s seconds of a drive lasting duration_s (trapezoidal profile).
  double ArcLengthAt(double t_s, double duration_s) const;
  // Duration of a drive covering `laps` laps with this profile.
  double DurationForLaps(double laps) const;

 private:
  Eigen::Vector2d center_;
  double half_x_m_, half_y_m_, radius_m_;
  double speed_mps_, accel_mps2_, start_offset_m_;
  double length_m_;
};

}  // namespace icgm::sim
