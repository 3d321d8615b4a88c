#include "core/nav/local_planner.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <mutex>
#include <sstream>

#include <ompl/base/SpaceInformation.h>
#include <ompl/base/StateSampler.h>
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

void QuietOmplOnce() {
  static std::once_flag once;
  std::call_once(once, [] { ompl::msg::setLogLevel(ompl::msg::LOG_WARN); });
}

// Uniform SE(2) samples from the sampler's own generator, seeded per plan (OMPL's default
// sampler takes its seed from a process-wide sequence: plans would depend on earlier ones).
class SeededSe2Sampler : public ob::StateSampler {
 public:
  SeededSe2Sampler(const ob::StateSpace* space, std::uint_fast32_t seed) : StateSampler(space) {
    rng_.setLocalSeed(seed);
  }
  void sampleUniform(ob::State* state) override {
    const ob::RealVectorBounds& b = space_->as<ob::SE2StateSpace>()->getBounds();
    auto* s = state->as<ob::SE2StateSpace::StateType>();
    s->setXY(rng_.uniformReal(b.low[0], b.high[0]), rng_.uniformReal(b.low[1], b.high[1]));
    s->setYaw(rng_.uniformReal(-M_PI, M_PI));
  }
  void sampleUniformNear(ob::State* state, const ob::State* near, double distance) override {
    const auto* n = near->as<ob::SE2StateSpace::StateType>();
    auto* s = state->as<ob::SE2StateSpace::StateType>();
    s->setXY(n->getX() + rng_.uniformReal(-distance, distance),
             n->getY() + rng_.uniformReal(-distance, distance));
    s->setYaw(n->getYaw() + rng_.uniformReal(-distance, distance));
    space_->enforceBounds(state);
  }
  void sampleGaussian(ob::State* state, const ob::State* mean, double stddev) override {
    const auto* m = mean->as<ob::SE2StateSpace::StateType>();
    auto* s = state->as<ob::SE2StateSpace::StateType>();
    s->setXY(rng_.gaussian(m->getX(), stddev), rng_.gaussian(m->getY(), stddev));
    s->setYaw(rng_.gaussian(m->getYaw(), stddev));
    space_->enforceBounds(state);
  }
};

class SeededRrtConnect : public og::RRTConnect {
 public:
  SeededRrtConnect(const ob::SpaceInformationPtr& si, std::uint_fast32_t seed) : RRTConnect(si) {
    rng_.setLocalSeed(seed);
  }
};

class SeededSimplifier : public og::PathSimplifier {
 public:
  SeededSimplifier(const ob::SpaceInformationPtr& si, std::uint_fast32_t seed)
      : PathSimplifier(si) {
    rng_.setLocalSeed(seed);
  }
};

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

LocalPlanner::LocalPlanner(LocalPlannerOptions options) : options_(options) { QuietOmplOnce(); }

LocalPlanner::~LocalPlanner() = default;

bool LocalPlanner::StateFree(const Eigen::Vector2d& p, const Eigen::Vector2d& start,
                             const ObstacleGrid& grid, double required_m) const {
  const double clearance = grid.Clearance(p.x(), p.y());
  if (clearance >= (required_m < 0.0 ? grid.inflation_m() : required_m)) return true;
  // Escaping from inside the inflation: only the footprint itself must stay free.
  return (p - start).norm() <= options_.start_escape_m &&
         clearance >= grid.options().robot_radius_m;
}

bool LocalPlanner::SegmentFree(const Eigen::Vector2d& a, const Eigen::Vector2d& b,
                               const ObstacleGrid& grid) const {
  return SegmentFree(a, b, grid, a);
}

bool LocalPlanner::SegmentFree(const Eigen::Vector2d& a, const Eigen::Vector2d& b,
                               const ObstacleGrid& grid, const Eigen::Vector2d& escape_from,
                               double clearance_m) const {
  const double required =
      clearance_m < 0.0 ? -1.0 : grid.options().robot_radius_m + clearance_m;
  const double len = (b - a).norm();
  const int n = std::max(1, static_cast<int>(std::ceil(len / options_.check_resolution_m)));
  for (int i = 0; i <= n; ++i) {
    if (!StateFree(a + (b - a) * (static_cast<double>(i) / n), escape_from, grid, required)) {
      return false;
    }
  }
  return true;
}

Status LocalPlanner::Plan(const Pose2D& start, const Pose2D& goal, const ObstacleGrid& grid,
                          LocalPath* path, LocalPlanStats* stats, double clearance_m) const {
  const double required =
      clearance_m < 0.0 ? -1.0 : grid.options().robot_radius_m + clearance_m;
  LocalPlanStats local_stats;
  LocalPlanStats& st = stats ? *stats : local_stats;
  st = LocalPlanStats();
  const Eigen::Vector2d s = start.position(), g = goal.position();
  if (grid.Clearance(s.x(), s.y()) < grid.options().robot_radius_m) {
    return Status::Error("local planner: the robot's footprint touches an obstacle");
  }
  if (!StateFree(g, s, grid, required)) {
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
  const auto seed = static_cast<std::uint_fast32_t>(std::max(1, options_.seed));
  space->setStateSamplerAllocator([seed](const ob::StateSpace* sp) -> ob::StateSamplerPtr {
    return std::make_shared<SeededSe2Sampler>(sp, seed);
  });

  og::SimpleSetup setup(space);
  int checks = 0;
  setup.setStateValidityChecker([this, s, &grid, &checks, required](const ob::State* state) {
    ++checks;
    const auto* se2 = state->as<ob::SE2StateSpace::StateType>();
    return StateFree(Eigen::Vector2d(se2->getX(), se2->getY()), s, grid, required);
  });
  setup.getSpaceInformation()->setStateValidityCheckingResolution(
      options_.check_resolution_m / space->getMaximumExtent());
  auto planner = std::make_shared<SeededRrtConnect>(setup.getSpaceInformation(), seed + 1);
  planner->setRange(options_.range_m);
  setup.setPlanner(planner);
  ob::ScopedState<ob::SE2StateSpace> from(space), to(space);
  from->setXY(s.x(), s.y());
  from->setYaw(start.yaw_rad);
  to->setXY(g.x(), g.y());
  to->setYaw(goal.yaw_rad);
  setup.setStartAndGoalStates(from, to);
  setup.setup();

  // The work budget ends planning; the wall clock only as a safety stop.
  const int budget = options_.max_state_checks;
  const ob::PlannerTerminationCondition out_of_work([&checks, budget] { return checks >= budget; });
  const auto t0 = std::chrono::steady_clock::now();
  const ob::PlannerStatus solved = setup.getPlanner()->solve(ob::plannerOrTerminationCondition(
      out_of_work, ob::timedPlannerTerminationCondition(options_.time_cap_ms * 1e-3)));
  const double used_ms =
      std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
  st.state_checks = checks;
  st.time_cap_hit = checks < budget && used_ms >= options_.time_cap_ms;
  if (solved != ob::PlannerStatus::EXACT_SOLUTION) {
    std::ostringstream reason;
    reason << "local planner: no path to (" << g.x() << ", " << g.y() << ") within ";
    if (st.time_cap_hit) {
      reason << "the " << options_.time_cap_ms << " ms time cap (" << checks
             << " state checks; blocked)";
    } else {
      reason << budget << " state checks (blocked)";
    }
    return Status::Error(reason.str());
  }
  og::PathGeometric solution =
      *setup.getProblemDefinition()->getSolutionPath()->as<og::PathGeometric>();
  // A fixed amount of simplification (OMPL's simplify() runs on the clock).
  SeededSimplifier simplifier(setup.getSpaceInformation(), seed + 2);
  const unsigned steps = static_cast<unsigned>(options_.simplify_steps);
  simplifier.reduceVertices(solution, steps, steps);
  simplifier.shortcutPath(solution, steps, steps);
  simplifier.reduceVertices(solution, steps, steps);
  simplifier.collapseCloseVertices(solution, steps, steps);

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
