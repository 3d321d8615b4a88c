#include "core/nav/local_planner.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <mutex>
#include <sstream>

#include <ompl/base/SpaceInformation.h>
#include <ompl/base/spaces/SE2StateSpace.h>
#include <ompl/geometric/PathSimplifier.h>
#include <ompl/geometric/SimpleSetup.h>
#include <ompl/geometric/planners/rrt/RRTConnect.h>
#include <ompl/util/Console.h>
#include <ompl/util/RandomNumbers.h>

namespace icgm {
namespace {

namespace ob = ompl::base;
namespace og = ompl::geometric;

// OMPL's generator can be seeded once per process, before its first use.
void SeedOmplOnce(int seed) {
  static std::once_flag once;
  std::call_once(once, [seed] {
    ompl::msg::setLogLevel(ompl::msg::LOG_WARN);
    if (seed > 0) ompl::RNG::setSeed(static_cast<std::uint_fast32_t>(seed));
  });
}

}  // namespace

double PolylineLength(const std::vector<Eigen::Vector2d>& points) {
  double length = 0.0;
  for (size_t i = 1; i < points.size(); ++i) length += (points[i] - points[i - 1]).norm();
  return length;
}

std::vector<Eigen::Vector2d> ResamplePolyline(const std::vector<Eigen::Vector2d>& points,
                                              double spacing_m) {
  if (points.size() < 2 || spacing_m <= 0.0) return points;
  std::vector<Eigen::Vector2d> out{points.front()};
  double carry = 0.0;  // distance along the polyline since the last output point
  for (size_t i = 1; i < points.size(); ++i) {
    const Eigen::Vector2d a = points[i - 1], b = points[i];
    const double len = (b - a).norm();
    double s = spacing_m - carry;
    while (s < len) {
      out.push_back(a + (b - a) * (s / len));
      s += spacing_m;
    }
    carry = len - (s - spacing_m);
  }
  if ((out.back() - points.back()).norm() > 1e-9) {
    if ((out.back() - points.back()).norm() < 0.3 * spacing_m && out.size() > 1) out.pop_back();
    out.push_back(points.back());
  }
  return out;
}

LocalPlanner::LocalPlanner(LocalPlannerOptions options) : options_(options) {
  SeedOmplOnce(options_.seed);
}

LocalPlanner::~LocalPlanner() = default;

bool LocalPlanner::StateFree(const Eigen::Vector2d& p, const Eigen::Vector2d& start,
                             const ObstacleGrid& grid) const {
  const double clearance = grid.Clearance(p.x(), p.y());
  if (clearance >= grid.inflation_m()) return true;
  // Escaping from inside the inflation: only the footprint itself must stay free.
  return (p - start).norm() <= options_.start_escape_m &&
         clearance >= grid.options().robot_radius_m;
}

bool LocalPlanner::SegmentFree(const Eigen::Vector2d& a, const Eigen::Vector2d& b,
                               const ObstacleGrid& grid) const {
  const double len = (b - a).norm();
  const int n = std::max(1, static_cast<int>(std::ceil(len / options_.check_resolution_m)));
  for (int i = 0; i <= n; ++i) {
    if (!StateFree(a + (b - a) * (static_cast<double>(i) / n), a, grid)) return false;
  }
  return true;
}

Status LocalPlanner::Plan(const Pose2D& start, const Pose2D& goal, const ObstacleGrid& grid,
                          LocalPath* path) const {
  const auto t0 = std::chrono::steady_clock::now();
  const Eigen::Vector2d s = start.position(), g = goal.position();
  if (grid.Clearance(s.x(), s.y()) < grid.options().robot_radius_m) {
    return Status::Error("local planner: the robot's footprint touches an obstacle");
  }
  if (!StateFree(g, s, grid)) {
    return Status::Error("local planner: goal (" + std::to_string(g.x()) + ", " +
                         std::to_string(g.y()) + ") is inside an obstacle's inflation");
  }
  auto space = std::make_shared<ob::SE2StateSpace>();
  const Eigen::Vector2d centre = 0.5 * (s + g);
  const double half = std::max(0.5 * options_.window_m, 0.5 * (g - s).norm() + 1.0);
  ob::RealVectorBounds bounds(2);
  bounds.setLow(0, centre.x() - half);
  bounds.setHigh(0, centre.x() + half);
  bounds.setLow(1, centre.y() - half);
  bounds.setHigh(1, centre.y() + half);
  space->setBounds(bounds);

  og::SimpleSetup setup(space);
  setup.setStateValidityChecker([this, s, &grid](const ob::State* state) {
    const auto* se2 = state->as<ob::SE2StateSpace::StateType>();
    return StateFree(Eigen::Vector2d(se2->getX(), se2->getY()), s, grid);
  });
  setup.getSpaceInformation()->setStateValidityCheckingResolution(
      options_.check_resolution_m / space->getMaximumExtent());
  auto planner = std::make_shared<og::RRTConnect>(setup.getSpaceInformation());
  planner->setRange(options_.range_m);
  setup.setPlanner(planner);
  ob::ScopedState<ob::SE2StateSpace> from(space), to(space);
  from->setXY(s.x(), s.y());
  from->setYaw(start.yaw_rad);
  to->setXY(g.x(), g.y());
  to->setYaw(goal.yaw_rad);
  setup.setStartAndGoalStates(from, to);
  setup.setup();

  const double budget_s = options_.time_budget_ms * 1e-3;
  const ob::PlannerStatus solved = setup.getPlanner()->solve(0.7 * budget_s);
  if (solved != ob::PlannerStatus::EXACT_SOLUTION) {
    std::ostringstream reason;
    reason << "local planner: no path to (" << g.x() << ", " << g.y() << ") within "
           << options_.time_budget_ms << " ms (blocked)";
    return Status::Error(reason.str());
  }
  og::PathGeometric solution =
      *setup.getProblemDefinition()->getSolutionPath()->as<og::PathGeometric>();
  const double used_s =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  og::PathSimplifier simplifier(setup.getSpaceInformation());
  const ob::PlannerTerminationCondition ptc =
      ob::timedPlannerTerminationCondition(std::max(1e-3, budget_s - used_s));
  simplifier.simplify(solution, ptc);

  std::vector<Eigen::Vector2d> points;
  for (const ob::State* state : solution.getStates()) {
    const auto* se2 = state->as<ob::SE2StateSpace::StateType>();
    points.emplace_back(se2->getX(), se2->getY());
  }
  points.front() = s;
  points.back() = g;
  path->points_m = ResamplePolyline(points, options_.sample_spacing_m);
  path->length_m = PolylineLength(path->points_m);
  return Status::Ok();
}

}  // namespace icgm
