#include "core/nav/dubins_rejoin.h"

#include <algorithm>
#include <cmath>
#include <vector>

#include <ompl/base/ScopedState.h>
#include <ompl/base/spaces/DubinsStateSpace.h>

namespace icgm {
namespace {

constexpr double kTwoPi = 2.0 * M_PI;
// A start whose curve OMPL cannot take is turned by this (a negligible change of the curve) ...
constexpr double kStartNudgeRad = 1e-5;
// ... when a first arc lies this close to no turn or a full turn.
constexpr double kFullTurnWindowRad = 1e-6;

double WrapTwoPi(double a) { return a - kTwoPi * std::floor(a / kTwoPi); }

// OMPL 1.5's Dubins solver snaps an arc angle within 5e-7 rad of a full turn to zero and then
// checks its own turn-straight-turn solution, which is then off by the straight part's length
// (in turning radii) times that angle: past 2e-6 the check aborts the process. An ordinary
// rejoin does it (3.6 cm beside the route, heading along it, a join point 0.67 m ahead at a
// 0.1 m radius: the right-straight-left curve's first arc 3.9e-7 rad short of a full turn).
// True when the first arc of one of the four turn-straight-turn curves from `from` to `to`
// lies within kFullTurnWindowRad of no turn (or a full one). The arcs from the curves'
// tangent geometry, in turning radii, with the heading angles taken from the chord.
bool FirstArcNearFullTurn(const Pose2D& from, const Pose2D& to, double radius_m) {
  const double dx = to.x_m - from.x_m, dy = to.y_m - from.y_m;
  const double d = std::hypot(dx, dy) / radius_m;
  const double chord = std::atan2(dy, dx);
  const double a = WrapTwoPi(from.yaw_rad - chord), b = WrapTwoPi(to.yaw_rad - chord);
  const double ca = std::cos(a), sa = std::sin(a), cb = std::cos(b), sb = std::sin(b);
  const double cross = ca * cb + sa * sb;
  std::vector<double> first_arcs;
  // Both turns the same way (left-left, right-right): the outer tangent.
  if (2.0 + d * d - 2.0 * (cross - d * (sa - sb)) >= 0.0) {
    first_arcs.push_back(std::atan2(cb - ca, d + sa - sb) - a);
  }
  if (2.0 + d * d - 2.0 * (cross + d * (sa - sb)) >= 0.0) {
    first_arcs.push_back(a - std::atan2(ca - cb, d - sa + sb));
  }
  // Opposite turns (right-left, left-right): the inner tangent, whose length enters the angle.
  const double rl = d * d - 2.0 + 2.0 * (cross - d * (sa + sb));
  if (rl >= 0.0) {
    first_arcs.push_back(a - std::atan2(ca + cb, d - sa - sb) + std::atan2(2.0, std::sqrt(rl)));
  }
  const double lr = d * d - 2.0 + 2.0 * (cross + d * (sa + sb));
  if (lr >= 0.0) {
    first_arcs.push_back(std::atan2(-ca - cb, d + sa + sb) - std::atan2(-2.0, std::sqrt(lr)) - a);
  }
  for (const double t : first_arcs) {
    const double w = WrapTwoPi(t);
    if (w < kFullTurnWindowRad || kTwoPi - w < kFullTurnWindowRad) return true;
  }
  return false;
}

}  // namespace

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
  Pose2D start = from;
  for (int i = 0; i < 4 && FirstArcNearFullTurn(start, to, radius_m); ++i) {
    start.yaw_rad += kStartNudgeRad;
  }
  a->setXY(start.x_m, start.y_m);
  a->setYaw(start.yaw_rad);
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
