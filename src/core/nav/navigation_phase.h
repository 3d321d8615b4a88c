// What the navigator is doing, in words, for a log a user reads while the robot drives (as
// move_base logs its planner and its recoveries): following the route, waiting for localization,
// stopped for an obstacle ahead (with the reason), avoiding (a detour, or waiting for one),
// rejoining the route after a manoeuvre, yielding to a walker (the crowd guard's action),
// turning in place at the goal to its orientation.
//
// PhaseLog reports the changes: a new phase is reported once it has lasted min_s (a phase that
// flickers for a cycle or two is not), and a phase other than following the route that goes on
// is reported again every repeat_s, with how long it has lasted, so a robot that stands for a
// long time says why.
#pragma once

#include <optional>
#include <string>

#include "core/nav/navigator.h"

namespace icgm {

// The phase of an active goal in a few words ("following the route", "safety stop: ...", ...).
std::string DescribePhase(const NavigationStatus& status);

class PhaseLog {
 public:
  explicit PhaseLog(double min_s = 0.5, double repeat_s = 10.0)
      : min_s_(min_s), repeat_s_(repeat_s) {}

  // The line to log after this control cycle, if any (the phase and the distance to the goal).
  std::optional<std::string> Update(double now_s, const NavigationStatus& status);
  // A new goal: nothing reported yet.
  void Reset();

 private:
  double min_s_, repeat_s_;
  std::string reported_;   // the phase last reported ("" at the start of a goal)
  std::string candidate_;  // the phase now, since candidate_since_s_
  double candidate_since_s_ = 0.0;
  double last_report_s_ = 0.0;
};

}  // namespace icgm
