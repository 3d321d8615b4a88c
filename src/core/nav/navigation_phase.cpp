#include "core/nav/navigation_phase.h"

#include "core/common/fixed_text.h"

namespace icgm {

namespace {
constexpr char kFollowing[] = "following the route";
}  // namespace

std::string DescribePhase(const NavigationStatus& s) {
  switch (s.state) {
    case NavigationState::kIdle:
      return "idle";
    case NavigationState::kReached:
      return "reached";
    case NavigationState::kTurningToGoal:
      return "turning to the goal's orientation";
    case NavigationState::kAborted:
      return "aborted: " + s.reason;
    case NavigationState::kSafetyStop:
      return "safety stop" + (s.reason.empty() ? std::string() : ": " + s.reason);
    case NavigationState::kActive:
      break;
  }
  if (!s.reason.empty()) return s.reason;  // waiting for localization, blocked, yielding, ...
  if (s.avoiding) return "avoiding an obstacle on the route";
  if (s.rejoining) return "rejoining the route";
  return kFollowing;
}

std::optional<std::string> PhaseLog::Update(double now_s, const NavigationStatus& status) {
  const std::string phase = DescribePhase(status);
  if (phase != candidate_) {
    candidate_ = phase;
    candidate_since_s_ = now_s;
  }
  const double lasted = now_s - candidate_since_s_;
  const std::string where = " (" + FormatFixed(status.distance_to_goal_m, 2) + " m from the goal)";
  if (candidate_ != reported_ && lasted >= min_s_) {
    reported_ = candidate_;
    last_report_s_ = now_s;
    return candidate_ + where;
  }
  if (candidate_ == reported_ && candidate_ != kFollowing && now_s - last_report_s_ >= repeat_s_) {
    last_report_s_ = now_s;
    return "still " + candidate_ + " after " + FormatFixed(lasted, 1) + " s" + where;
  }
  return std::nullopt;
}

void PhaseLog::Reset() {
  reported_.clear();
  candidate_.clear();
  candidate_since_s_ = last_report_s_ = 0.0;
}

}  // namespace icgm
