#include "core/nav/crowd_guard.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

namespace icgm {
namespace {

// CrowdGuardOptions::own_motion_only: a command counts as closing a walker's gap when its
// smallest gap is this much below standing still's.
constexpr double kOwnMotionMarginM = 0.05;

double Ramp(double from, double to, double max_step) {
  return from + std::clamp(to - from, -max_step, max_step);
}

// One rollout step of a unicycle (midpoint heading).
void StepUnicycle(double v, double w, double dt, Pose2D* p) {
  const double yaw_mid = p->yaw_rad + 0.5 * w * dt;
  p->x_m += v * dt * std::cos(yaw_mid);
  p->y_m += v * dt * std::sin(yaw_mid);
  p->yaw_rad = WrapAngleRad(p->yaw_rad + w * dt);
}

// The footprint at `moved` comes closer than `gap` to `disc` and closer than at `stood`.
bool ClosesOn(const Eigen::Vector2d& moved, const Eigen::Vector2d& stood, const Disc& disc,
              double robot_radius_m, double gap) {
  const double moved_gap = (moved - disc.centre_m).norm() - disc.radius_m - robot_radius_m;
  if (moved_gap >= gap) return false;
  return moved_gap < (stood - disc.centre_m).norm() - disc.radius_m - robot_radius_m - 1e-4;
}

}  // namespace

CrowdGuard::CrowdGuard(CrowdGuardOptions options) : options_(options) {}

CrowdGuard::Rollout CrowdGuard::Roll(const Pose2D& pose, const VelocityCommand& current,
                                     const VelocityCommand& target, double robot_radius_m,
                                     const ObstacleGrid& grid,
                                     const ObstacleTracker& tracker) const {
  Rollout out;
  out.gap_m = tracker.PredictedClearance(pose.position(), 0.0) - robot_radius_m;
  double stood_gap = out.gap_m;  // own_motion_only: the smallest gap standing still
  const double start_static = grid.Clearance(pose.x_m, pose.y_m);
  // The gap is kept from every obstacle cell too (a walker the tracker does not follow yet, or
  // one standing): an alternative may not bring the footprint closer than min_gap_m to one
  // (or closer than it already is).
  const double static_needed = std::min(robot_radius_m + options_.min_gap_m, start_static);
  // Standing walkers: all (standing_walkers), or those out of view only (unseen_walkers).
  const bool standing = options_.standing_walkers || options_.unseen_walkers;
  const bool unseen_only = !options_.standing_walkers;
  const double standing_needed =
      standing ? std::min(options_.min_gap_m,
                          tracker.StandingWalkerClearance(pose.position(), 0.0, unseen_only) -
                              robot_radius_m)
               : -std::numeric_limits<double>::infinity();
  // Walker bodies: the gap this command must keep (wider when it creeps).
  double body_gap = options_.body_gap_m;
  if (std::abs(target.linear_mps) < options_.body_creep_speed_mps) {
    body_gap = std::max(body_gap, options_.body_creep_gap_m);
  }
  std::vector<const TrackedObstacle*> bodies;
  if (body_gap > 0.0) {
    for (const TrackedObstacle& t : tracker.tracks()) {
      if (options_.body_all_tracks || ObstacleTracker::IsWalker(t)) bodies.push_back(&t);
    }
  }
  std::vector<const TrackedObstacle*> remembered;
  if (options_.remembered_gap_m > 0.0) {
    for (const TrackedObstacle& t : tracker.tracks()) {
      const Disc d = tracker.RememberedDisc(t, 0.0);
      if (t.remembered && (pose.position() - d.centre_m).norm() - d.radius_m - robot_radius_m <
                              options_.remembered_near_m) {
        remembered.push_back(&t);
      }
    }
  }
  Pose2D p = pose;
  double v = current.linear_mps, w = current.angular_radps;
  const double dt = options_.step_s;
  const int steps = std::max(1, static_cast<int>(std::lround(options_.horizon_s / dt)));
  for (int k = 1; k <= steps; ++k) {
    v = Ramp(v, target.linear_mps, options_.acceleration_mps2 * dt);
    w = Ramp(w, target.angular_radps, options_.angular_acceleration_radps2 * dt);
    StepUnicycle(v, w, dt, &p);
    if (k * dt <= options_.body_horizon_s + 1e-9) {
      for (const TrackedObstacle* t : bodies) {
        if (ClosesOn(p.position(), pose.position(), tracker.BodyDisc(*t, k * dt), robot_radius_m,
                     body_gap)) {
          out.body_ok = false;
        }
      }
    }
    if (k * dt <= options_.remembered_horizon_s + 1e-9) {
      for (const TrackedObstacle* t : remembered) {
        if (ClosesOn(p.position(), pose.position(), tracker.RememberedDisc(*t, k * dt),
                     robot_radius_m, options_.remembered_gap_m)) {
          out.remembered_ok = false;
        }
      }
    }
    out.gap_m = std::min(out.gap_m, tracker.PredictedClearance(p.position(), k * dt) -
                                        robot_radius_m);
    if (options_.own_motion_only) {
      stood_gap = std::min(stood_gap, tracker.PredictedClearance(pose.position(), k * dt) -
                                          robot_radius_m);
    }
    if (grid.Clearance(p.x_m, p.y_m) < static_needed - 1e-6) out.static_ok = false;
    if (standing &&
        tracker.StandingWalkerClearance(p.position(), k * dt, unseen_only) - robot_radius_m <
            standing_needed - 1e-6) {
      out.standing_ok = false;
    }
  }
  // The walkers' own motion closes the gap as much with the robot standing: not the command's.
  // (Within a margin: the walkers' predicted velocities are estimates, and the same walker is
  // met later, farther along its prediction, by a moving robot.)
  if (options_.own_motion_only && out.gap_m >= stood_gap - kOwnMotionMarginM) {
    out.gap_m = std::numeric_limits<double>::infinity();
  }
  out.end = p;
  return out;
}

GuardResult CrowdGuard::Check(const Pose2D& pose, const VelocityCommand& current,
                              const VelocityCommand& wanted, double robot_radius_m,
                              const ObstacleGrid& grid, const ObstacleTracker& tracker) const {
  GuardResult result;
  result.command = wanted;
  const Rollout nominal = Roll(pose, current, wanted, robot_radius_m, grid, tracker);
  result.predicted_gap_m = nominal.gap_m;
  const double caution = std::max(options_.caution_gap_m, options_.min_gap_m);
  const bool nominal_clear = nominal.standing_ok && nominal.body_ok &&
                             (nominal.remembered_ok || options_.remembered_alternatives_only);
  if (nominal.gap_m >= caution && nominal_clear) return result;

  struct Candidate {
    VelocityCommand cmd;
    const char* action;
  };
  const double v = wanted.linear_mps, w = wanted.angular_radps;
  const double r = options_.reverse_speed_mps, s = options_.swerve_speed_mps,
               t = options_.turn_radps;
  std::vector<Candidate> candidates{{{0.66 * v, 0.66 * w}, "slow"}, {{0.33 * v, 0.33 * w}, "slow"},
                                    {{0.0, 0.0}, "stop"},           {{0.0, t}, "turn"},
                                    {{0.0, -t}, "turn"},            {{s, t}, "swerve"},
                                    {{s, -t}, "swerve"},            {{s, 0.0}, "swerve"}};
  if (r > 0.0) {
    candidates.insert(candidates.end(), {{{-r, 0.0}, "back off"},
                                         {{-r, t}, "back off"},
                                         {{-r, -t}, "back off"}});
  }
  // Closest to the wanted motion among those that keep the gap; else the largest gap.
  const auto miss = [&](const Rollout& roll) {
    const double dyaw = WrapAngleRad(roll.end.yaw_rad - nominal.end.yaw_rad);
    return (roll.end.position() - nominal.end.position()).norm() + 0.2 * std::abs(dyaw);
  };
  int best_caution = -1, best_keep = -1, best_gap = -1;
  double best_caution_miss = std::numeric_limits<double>::infinity();
  double best_keep_miss = std::numeric_limits<double>::infinity();
  double best_gap_m = -std::numeric_limits<double>::infinity();
  std::vector<Rollout> rolls;
  for (size_t i = 0; i < candidates.size(); ++i) {
    rolls.push_back(Roll(pose, current, candidates[i].cmd, robot_radius_m, grid, tracker));
    const Rollout& roll = rolls.back();
    if (!roll.Clear()) continue;
    if (roll.gap_m >= caution && miss(roll) < best_caution_miss) {
      best_caution_miss = miss(roll);
      best_caution = static_cast<int>(i);
    }
    if (roll.gap_m >= options_.min_gap_m && miss(roll) < best_keep_miss) {
      best_keep_miss = miss(roll);
      best_keep = static_cast<int>(i);
    }
    if (roll.gap_m > best_gap_m + 1e-3) {
      best_gap_m = roll.gap_m;
      best_gap = static_cast<int>(i);
    }
  }
  // The wanted command keeps min_gap_m and nothing keeps the caution gap: go on as wanted.
  if (best_caution < 0 && nominal.gap_m >= options_.min_gap_m && nominal_clear) return result;
  if (best_caution >= 0) best_keep = best_caution;
  const int pick = best_keep >= 0 ? best_keep : best_gap;
  result.intervened = true;
  if (pick < 0) {  // every alternative runs into the scenery: stand still
    result.command = VelocityCommand();
    result.kept_gap = false;
    result.action = "stop";
    return result;
  }
  result.command = candidates[pick].cmd;
  result.action = candidates[pick].action;
  result.kept_gap = best_keep >= 0;
  result.predicted_gap_m = rolls[pick].gap_m;
  return result;
}

bool CrowdGuard::KeepsGap(const Pose2D& pose, const VelocityCommand& cmd, double robot_radius_m,
                          const ObstacleTracker& tracker) const {
  const double margin = options_.gap_filter_m;
  const double dt = options_.step_s;
  const int steps = std::max(1, static_cast<int>(std::lround(options_.gap_filter_horizon_s / dt)));
  Pose2D p = pose;
  for (int k = 1; k <= steps; ++k) {
    StepUnicycle(cmd.linear_mps, cmd.angular_radps, dt, &p);
    for (const TrackedObstacle& t : tracker.tracks()) {
      if (!ObstacleTracker::IsWalker(t)) continue;
      const Eigen::Vector2d w = tracker.Predict(t, k * dt);
      const double moved = (p.position() - w).norm() - t.radius_m - robot_radius_m;
      if (moved >= margin) continue;
      const double stood = (pose.position() - w).norm() - t.radius_m - robot_radius_m;
      if (moved < stood - 1e-4) return false;
    }
  }
  return true;
}

VelocityCommand CrowdGuard::FilterGap(const Pose2D& pose, const VelocityCommand& wanted,
                                      double robot_radius_m, const ObstacleTracker& tracker) const {
  if (options_.gap_filter_m <= 0.0 || wanted.linear_mps == 0.0) return wanted;
  if (KeepsGap(pose, wanted, robot_radius_m, tracker)) return wanted;
  // Forward speed first (the turn may be what steers away), then the turn with it.
  constexpr double kScales[] = {0.75, 0.5, 0.25, 0.125};
  for (const double f : kScales) {
    for (const double g : {1.0, 0.5, 0.0}) {
      const VelocityCommand c{f * wanted.linear_mps, g * wanted.angular_radps};
      if (KeepsGap(pose, c, robot_radius_m, tracker)) return c;
    }
  }
  return VelocityCommand{0.0, wanted.angular_radps};
}

VelocityCommand CrowdGuard::BlindSideSpeed(const Pose2D& pose, const VelocityCommand& wanted,
                                           double robot_radius_m,
                                           const ObstacleTracker& tracker) const {
  const double cap = options_.blind_side_speed_mps;
  if (cap <= 0.0 || wanted.linear_mps <= cap) return wanted;
  bool near = false;
  for (const TrackedObstacle& t : tracker.tracks()) {
    if (!t.was_moving || !tracker.Unseen(t)) continue;
    const double gap =
        (pose.position() - tracker.Predict(t, 0.0)).norm() - t.radius_m - robot_radius_m;
    near = near || gap < options_.blind_side_gap_m;
  }
  if (!near) return wanted;
  const double f = cap / wanted.linear_mps;
  return VelocityCommand{cap, f * wanted.angular_radps};
}

VelocityCommand CrowdGuard::ApproachSpeed(const Pose2D& pose, const VelocityCommand& wanted,
                                          double robot_radius_m,
                                          const ObstacleTracker& tracker) const {
  const CrowdGuardOptions& o = options_;
  if (o.approach_gap_m <= 0.0 || wanted.linear_mps <= 0.0) return wanted;
  const Eigen::Vector2d heading(std::cos(pose.yaw_rad), std::sin(pose.yaw_rad));
  double cap = wanted.linear_mps;
  for (const TrackedObstacle& t : tracker.tracks()) {
    if (!o.approach_all_tracks && !ObstacleTracker::IsWalker(t)) continue;
    const Eigen::Vector2d d = tracker.Predict(t, 0.0) - pose.position();
    const double gap = d.norm() - t.radius_m - robot_radius_m;
    if (gap >= o.approach_near_m || d.norm() < 1e-9) continue;
    const double towards = heading.dot(d.normalized());  // approach per unit forward speed
    if (towards <= 0.0) continue;
    cap = std::min(cap, o.approach_rate_per_s * std::max(0.0, gap - o.approach_gap_m) / towards);
  }
  return VelocityCommand{cap, wanted.angular_radps};
}

double CrowdGuard::EvasiveShortfall(const Pose2D& pose, const VelocityCommand& current,
                                    const VelocityCommand& target, double robot_radius_m,
                                    const ObstacleGrid& grid,
                                    const ObstacleTracker& tracker) const {
  struct Walker {
    Eigen::Vector2d p, v;
    double radius, needed;
  };
  std::vector<Walker> walkers;
  for (const TrackedObstacle& t : tracker.tracks()) {
    if (!ObstacleTracker::IsWalker(t)) continue;
    const Eigen::Vector2d p = tracker.Predict(t, 0.0);
    const Eigen::Vector2d v = tracker.Predict(t, 1.0) - p;
    const double gap = (p - pose.position()).norm() - t.radius_m - robot_radius_m;
    walkers.push_back({p, v, t.radius_m, std::min(options_.evasive_gap_m, gap)});
  }
  const double start_static = grid.Clearance(pose.x_m, pose.y_m);
  const double static_needed = std::min(robot_radius_m + options_.min_gap_m, start_static);
  const double space = options_.walker_personal_space_m;
  Pose2D p = pose;
  double v = current.linear_mps, w = current.angular_radps;
  const double dt = options_.step_s;
  const int steps = std::max(1, static_cast<int>(std::lround(options_.evasive_horizon_s / dt)));
  double shortfall = -std::numeric_limits<double>::infinity();
  for (int k = 1; k <= steps; ++k) {
    v = Ramp(v, target.linear_mps, options_.acceleration_mps2 * dt);
    w = Ramp(w, target.angular_radps, options_.angular_acceleration_radps2 * dt);
    StepUnicycle(v, w, dt, &p);
    if (grid.Clearance(p.x_m, p.y_m) < static_needed - 1e-6) {
      return std::numeric_limits<double>::infinity();
    }
    for (Walker& m : walkers) {
      // The walker's own step: taken unless it would enter its personal space around the
      // footprint (0: always).
      const Eigen::Vector2d next = m.p + m.v * dt;
      if (space <= 0.0 || (next - p.position()).norm() - m.radius - robot_radius_m >= space) {
        m.p = next;
      }
      const double gap = (m.p - p.position()).norm() - m.radius - robot_radius_m;
      shortfall = std::max(shortfall, m.needed - gap);
    }
  }
  return shortfall;
}

VelocityCommand CrowdGuard::Evade(const Pose2D& pose, const VelocityCommand& current,
                                  const VelocityCommand& wanted, double robot_radius_m,
                                  const ObstacleGrid& grid, const ObstacleTracker& tracker) const {
  if (options_.evasive_gap_m <= 0.0) return wanted;
  constexpr double kTolerance = 1e-4;
  if (EvasiveShortfall(pose, current, wanted, robot_radius_m, grid, tracker) <= kTolerance) {
    return wanted;
  }
  // The grid: the wanted arc slower, then other speeds and turns; backing off when allowed.
  std::vector<double> speeds{0.75 * wanted.linear_mps,  0.5 * wanted.linear_mps,
                             0.25 * wanted.linear_mps,  0.0,
                             options_.swerve_speed_mps, 0.5 * options_.swerve_speed_mps};
  if (options_.evasive_reverse_mps > 0.0) {
    speeds.push_back(-0.5 * options_.evasive_reverse_mps);
    speeds.push_back(-options_.evasive_reverse_mps);
  }
  const double t = options_.turn_radps;
  const std::vector<double> turns{wanted.angular_radps, 0.0, 0.5 * t, -0.5 * t, t, -t};
  VelocityCommand best, least;
  double best_miss = std::numeric_limits<double>::infinity();
  double least_shortfall = std::numeric_limits<double>::infinity();
  for (const double v : speeds) {
    for (const double w : turns) {
      const VelocityCommand c{v, w};
      const double shortfall = EvasiveShortfall(pose, current, c, robot_radius_m, grid, tracker);
      const double miss =
          std::abs(v - wanted.linear_mps) + 0.3 * std::abs(w - wanted.angular_radps);
      if (shortfall <= kTolerance && miss < best_miss) best_miss = miss, best = c;
      if (shortfall < least_shortfall - kTolerance) least_shortfall = shortfall, least = c;
    }
  }
  if (best_miss < std::numeric_limits<double>::infinity()) return best;
  // Nothing keeps every gap: the one falling least short, or standing.
  return least_shortfall < std::numeric_limits<double>::infinity() ? least : VelocityCommand();
}

bool CrowdGuard::StopsShort(const Pose2D& pose, const VelocityCommand& current,
                            const VelocityCommand& cmd, double robot_radius_m,
                            const ObstacleTracker& tracker) const {
  // Finer than the guard's rollouts: the stopping distances at creeping speed are centimetres.
  constexpr double kStepS = 0.05;
  struct Walker {
    const TrackedObstacle* track;
    double reach;  // footprint and disc radii
  };
  std::vector<Walker> walkers;
  for (const TrackedObstacle& t : tracker.tracks()) {
    if (ObstacleTracker::IsWalker(t)) walkers.push_back({&t, t.radius_m + robot_radius_m});
  }
  if (walkers.empty()) return true;
  // The base follows the command's arc: from its present speed towards the command (speeding up
  // as the guard's rollouts, slowing down at the braking deceleration) while it is held, then it
  // brakes to a stop.
  const double hold_s = options_.stopping_reaction_s + options_.stopping_margin_s;
  const double decel = options_.stopping_deceleration_mps2;
  const double target = std::max(0.0, cmd.linear_mps);
  const double curvature = target > 1e-9 ? cmd.angular_radps / target : 0.0;
  double v = std::max(0.0, current.linear_mps);
  Pose2D p = pose;
  for (double t = kStepS; v > 1e-9 || t <= hold_s + 1e-9; t += kStepS) {
    if (t <= hold_s + 1e-9) {
      v = v < target ? std::min(target, v + options_.acceleration_mps2 * kStepS)
                     : std::max(target, v - decel * kStepS);
    } else {
      v = std::max(0.0, v - decel * kStepS);
    }
    StepUnicycle(v, v * curvature, kStepS, &p);
    for (const Walker& m : walkers) {
      const Eigen::Vector2d w = tracker.Predict(*m.track, t);
      const double moved = (p.position() - w).norm() - m.reach;
      if (moved >= options_.stopping_gap_m) continue;
      const double stood = (pose.position() - w).norm() - m.reach;
      if (moved < stood - 1e-4) return false;
    }
  }
  return true;
}

VelocityCommand CrowdGuard::BrakeToStopShort(const Pose2D& pose, const VelocityCommand& current,
                                             const VelocityCommand& wanted, double robot_radius_m,
                                             const ObstacleTracker& tracker) const {
  if (options_.stopping_gap_m <= 0.0 || wanted.linear_mps <= 0.0) return wanted;
  if (StopsShort(pose, current, wanted, robot_radius_m, tracker)) return wanted;
  // The largest fraction of the speed (the same arc) from which the robot stops short.
  constexpr int kBisections = 8;
  double kept = 0.0, refused = 1.0;
  for (int i = 0; i < kBisections; ++i) {
    const double f = 0.5 * (kept + refused);
    const VelocityCommand c{f * wanted.linear_mps, f * wanted.angular_radps};
    (StopsShort(pose, current, c, robot_radius_m, tracker) ? kept : refused) = f;
  }
  // Standing: turning in place does not move the footprint.
  if (kept <= 0.0) return VelocityCommand{0.0, wanted.angular_radps};
  return VelocityCommand{kept * wanted.linear_mps, kept * wanted.angular_radps};
}

}  // namespace icgm
