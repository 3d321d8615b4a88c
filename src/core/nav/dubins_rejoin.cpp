#include "core/nav/dubins_rejoin.h"

#include <algorithm>
#include <cmath>

#include <ompl/base/ScopedState.h>
#include <ompl/base/spaces/DubinsStateSpace.h>

namespace icgm {

Pose2D TurnSettlingArc(const Pose2D& pose, double speed_mps, double turn_radps,
                       double angular_acceleration_radps2, double step_s,
                       std::vector<Eigen::Vector2d>* arc) {
  arc->clear();
  Pose2D p = pose;
  if (std::abs(turn_radps) < 1e-9 || std::abs(speed_mps) < 1e-9 ||
      angular_acceleration_radps2 <= 0.0 || step_s <= 0.0) {
    return p;
  }
  double w = turn_radps;
  const double dw = angular_acceleration_radps2 * step_s;
  while (std::abs(w) > 1e-9) {
    // The turn rate falls at the limit; the mean rate over the step moves the heading.
    const double next = std::abs(w) <= dw ? 0.0 : w - std::copysign(dw, w);
    const double mean_w = 0.5 * (w + next);
    const double mid = p.yaw_rad + 0.5 * mean_w * step_s;
    p.x_m += speed_mps * step_s * std::cos(mid);
    p.y_m += speed_mps * step_s * std::sin(mid);
    p.yaw_rad = WrapAngleRad(p.yaw_rad + mean_w * step_s);
    arc->push_back(p.position());
    w = next;
  }
  return p;
}

std::vector<Eigen::Vector2d> DubinsCurve(const Pose2D& from, const Pose2D& to, double radius_m,
                                         double spacing_m, double* length_m) {
  namespace ob = ompl::base;
  auto space = std::make_shared<ob::DubinsStateSpace>(radius_m);
  ob::ScopedState<ob::SE2StateSpace> a(space), b(space), s(space);
  a->setXY(from.x_m, from.y_m);
  a->setYaw(from.yaw_rad);
  b->setXY(to.x_m, to.y_m);
  b->setYaw(to.yaw_rad);
  ob::DubinsStateSpace::DubinsPath path = space->dubins(a.get(), b.get());
  bool first = false;  // interpolate along `path` (not computed again)
  // The path's length comes in turning radii.
  const double length = radius_m * path.length();
  if (length_m) *length_m = length;
  const int n = std::max(1, static_cast<int>(std::ceil(length / spacing_m)));
  std::vector<Eigen::Vector2d> points;
  points.reserve(n + 1);
  points.push_back(from.position());
  for (int i = 1; i < n; ++i) {
    space->interpolate(a.get(), b.get(), static_cast<double>(i) / n, first, path, s.get());
    points.emplace_back(s->getX(), s->getY());
  }
  points.push_back(to.position());
  return points;
}

}  // namespace icgm
