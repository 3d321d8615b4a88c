#include "core/sim/close_pass_escape.h"

#include <algorithm>
#include <cmath>

namespace icgm::sim {
namespace {

// The footprint's gap to each walker's body.
std::vector<double> WalkerGaps(const ClosedLoopSimulator& sim) {
  const std::vector<PedestrianState> people = sim.pedestrians();
  const PlanarPose& r = sim.planar_pose();
  std::vector<double> gaps(people.size());
  for (size_t i = 0; i < people.size(); ++i) {
    gaps[i] = std::hypot(people[i].x_m - r.x_m, people[i].y_m - r.y_m) -
              sim.pedestrian_radius_m(i) - sim.options().drive.robot_radius_m;
  }
  return gaps;
}

bool KeepsClearance(const ClosedLoopSimulator& start, const EscapePlan& plan, double lead_s,
                    const EscapeOptions& o) {
  ClosedLoopSimulator sim = start;
  std::vector<double> needed = WalkerGaps(start);
  for (double& n : needed) n = std::min(n, o.clearance_m);
  const int steps = static_cast<int>(std::lround((lead_s + o.window_s) / o.step_s));
  const int hold = static_cast<int>(std::lround(plan.hold_s / o.step_s));
  for (int k = 0; k < steps; ++k) {
    sim.Step(k < hold ? plan.command : VelocityCommand(), o.step_s);
    if (sim.StaticClearanceM() < 0.0) return false;
    const std::vector<double> gaps = WalkerGaps(sim);
    for (size_t i = 0; i < gaps.size(); ++i) {
      if (gaps[i] < needed[i] - 1e-6) return false;
    }
  }
  return true;
}

}  // namespace

std::vector<EscapePlan> EscapePlans(const EscapeOptions& o, double speed_mps) {
  const double s = o.sidestep_speed_mps, w = o.turn_radps, r = -o.reverse_speed_mps;
  std::vector<EscapePlan> plans{
      {"brake", {0.0, 0.0}, 0.0, false},           {"turn left", {0.0, w}, 1.0, false},
      {"turn right", {0.0, -w}, 1.0, false},       {"sidestep left", {s, w}, 0.6, false},
      {"sidestep right", {s, -w}, 0.6, false},     {"sidestep left long", {s, w}, 1.2, false},
      {"sidestep right long", {s, -w}, 1.2, false}};
  if (speed_mps > 0.05) {
    plans.push_back({"keep going", {speed_mps, 0.0}, 0.6, false});
    plans.push_back({"keep going long", {speed_mps, 0.0}, 1.2, false});
  }
  plans.push_back({"back off", {r, 0.0}, 0.6, true});
  plans.push_back({"back off long", {r, 0.0}, 1.2, true});
  plans.push_back({"back off left", {r, w}, 0.6, true});
  plans.push_back({"back off right", {r, -w}, 0.6, true});
  return plans;
}

int FindEscape(const ClosedLoopSimulator& start, const std::vector<EscapePlan>& plans,
               bool allow_reverse, double lead_s, const EscapeOptions& options) {
  for (size_t i = 0; i < plans.size(); ++i) {
    if (plans[i].reverses && !allow_reverse) continue;
    if (KeepsClearance(start, plans[i], lead_s, options)) return static_cast<int>(i);
  }
  return -1;
}

}  // namespace icgm::sim
