// A rejoin onto the route planned with a heading constraint: the path a differential-drive
// robot can follow from its current motion to a pose on the route, arriving along it.
//  - TurnSettlingArc: where the robot goes while its present turn rate is brought to zero at
//    the angular-acceleration limit (at its present speed). A robot that turns away from the
//    route when the route becomes free cannot turn towards it at once; a curve from its pose
//    would start with a turn it cannot make.
//  - DubinsCurve: the shortest forward path with a bounded curvature between two poses
//    (OMPL's DubinsStateSpace), sampled densely. Its end pose is a route point with the route's
//    direction, so the robot arrives tangentially instead of crossing the route at an angle.
// The Navigator tries several join points ahead and keeps the free curve that stays nearest the
// route (navigator.rejoin_dubins_radius_m).
#pragma once

#include <vector>

#include <Eigen/Core>

#include "core/nav/planar_pose.h"

namespace icgm {

// The arc driven at `speed_mps` while the turn rate goes from `turn_radps` to zero at
// `angular_acceleration_radps2`, sampled every `step_s` (the start pose excluded); returns the
// pose at its end. Empty arc (and `pose` returned) when there is no turn or no speed.
Pose2D TurnSettlingArc(const Pose2D& pose, double speed_mps, double turn_radps,
                       double angular_acceleration_radps2, double step_s,
                       std::vector<Eigen::Vector2d>* arc);

// The shortest Dubins curve (forward only, turning radius `radius_m`) from `from` to `to`,
// sampled every `spacing_m` or closer, both ends included. *length_m: its length.
std::vector<Eigen::Vector2d> DubinsCurve(const Pose2D& from, const Pose2D& to, double radius_m,
                                         double spacing_m, double* length_m);

}  // namespace icgm
