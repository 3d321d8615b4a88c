// Could the robot have kept its clearance from the walkers? Ground truth only, for the account of
// close passes (ClosePassLog): from a copy of the closed-loop simulator taken some steps before a
// close pass began, each escape of a fixed set (brake and stand; turn in place; keep the speed
// and pass; a sidestep arc; and, when allowed, backing off straight or turning), each held for a
// while and followed by braking to a stand, is driven in the simulator itself, whose crowd
// reacts to the robot's new motion as in the run. An escape counts when, over the window, the
// footprint comes no closer than clearance_m to any walker (nor closer than it already was to
// one already inside that) and does not touch walls or furniture. An oracle: it knows where
// every walker goes; what the navigator could perceive is not asked here.
#pragma once

#include <string>
#include <vector>

#include "core/common/velocity_command.h"
#include "core/sim/closed_loop_simulator.h"

namespace icgm::sim {

struct EscapeOptions {
  double clearance_m = 0.299;       // kept from every walker's body (the close-pass threshold)
  double window_s = 3.0;            // checked this long after the close pass began
  double step_s = 0.1;              // the control period
  double turn_radps = 0.8;          // turning in place, sidestepping and backing off
  double sidestep_speed_mps = 0.3;  // forward speed of a sidestep arc
  double reverse_speed_mps = 0.3;   // backing off (the simulated base allows it)
};

struct EscapePlan {
  std::string name;
  VelocityCommand command;
  double hold_s = 0.0;  // then zero
  bool reverses = false;
};

// The plans, forward-only ones first; `speed_mps`: the robot's speed now (keeping it and passing).
std::vector<EscapePlan> EscapePlans(const EscapeOptions& options, double speed_mps);

// The first of `plans` (with reverses only when `allow_reverse`) that keeps the clearance from
// `start` over lead_s + window_s; -1 when none does.
int FindEscape(const ClosedLoopSimulator& start, const std::vector<EscapePlan>& plans,
               bool allow_reverse, double lead_s, const EscapeOptions& options);

}  // namespace icgm::sim
