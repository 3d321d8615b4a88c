// Time-aware check of the velocity command against the walkers' predicted motion
// (ObstacleTracker): the command the tracking controller wants is rolled out over horizon_s
// (unicycle, acceleration-limited from the current command) and the footprint's predicted gap to
// every moving walker's disc at the same instant is measured. When the gap falls below
// min_gap_m the guard takes over and picks, among a fixed set of alternatives (the same arc
// slower, stop, turn in place, swerve forward; backing off only when reverse_speed_mps > 0: the
// camera does not see behind the robot, and in the crowd backing off ran into walkers there),
// the one closest to the wanted motion that keeps the gap (first caution_gap_m, wider, then
// min_gap_m; the wanted command itself when it keeps min_gap_m but no alternative keeps the
// caution gap); when none keeps it, the one with the
// largest gap (a walker heading straight at the robot: it swerves rather than waits). The
// footprint must also keep min_gap_m from the obstacle grid along every alternative (or not get
// closer to it than it already is): a swerve never runs into a walker standing beside. A dynamic-window selection in the spirit of Fox et al. 1997, with
// constant-velocity predictions of the walkers.
#pragma once

#include <string>

#include "core/common/velocity_command.h"
#include "core/nav/obstacle_grid.h"
#include "core/nav/obstacle_tracker.h"
#include "core/nav/planar_pose.h"

namespace icgm {

struct CrowdGuardOptions {
  double horizon_s = 1.5;            // rollout length
  double step_s = 0.1;               // rollout resolution
  double min_gap_m = 0.3;            // kept between the footprint and a walker's predicted disc
  // Wanted beyond min_gap_m: below it the guard already prefers an alternative (slower, ...)
  // that keeps this gap, and only then one that keeps min_gap_m (a walker that will cross
  // close ahead: slow down early). <= min_gap_m: off (the default: 0.4 m measured worse in the
  // crowd, more timeouts and contacts at speed from the side).
  double caution_gap_m = 0.3;
  double acceleration_mps2 = 1.0;    // the base's response in the rollouts
  double angular_acceleration_radps2 = 3.0;
  double reverse_speed_mps = 0.0;    // backing off (0: never; nothing is seen behind)
  double swerve_speed_mps = 0.4;     // driving out of a walker's way
  double turn_radps = 1.0;           // turning while backing off, swerving or in place
  // Standing walkers (tracks that moved once and stand or creep now: a walker waiting, or one
  // that does not yield sliding past the robot) count too: no command may bring the footprint
  // closer than min_gap_m to one's disc (or closer than it already is). The grid alone holds
  // the footprint min_gap_m from the cells the camera sees of a person, which lie inside the
  // person's body (arms, the far side). false: moving walkers only.
  bool standing_walkers = false;
  // Final gap filter (0: off): a command is refused (its forward speed scaled down, towards
  // zero, and then its turn) when, held for gap_filter_horizon_s, the footprint's own motion
  // would bring it closer than this to a walker's disc (a moving track or one that moved once),
  // closer than standing still would leave it at the same instant. Commands that keep or widen
  // the gap pass (turning in place never moves the circular footprint). The walkers stop at
  // their personal space and the robot's creeping, slowing or swerving motion closed the rest.
  double gap_filter_m = 0.0;
  double gap_filter_horizon_s = 0.5;
  // The blind side: the standing-walker rule above for the walkers out of the camera's view
  // only (tracks that moved once, stand or creep now and were not seen in the last update:
  // a walker that stopped beside the robot; with walker_tracker.standing_hold_s held where it
  // was last seen). The walkers in view are left to the grid, as without the option.
  bool unseen_walkers = false;
  // Blind-side speed (0: off): while the footprint is within blind_side_gap_m of the disc of a
  // walker out of view (a track that moved once, not seen in the last update), the forward
  // speed is capped at this (the turn scaled with it: the same arc).
  double blind_side_speed_mps = 0.0;
  double blind_side_gap_m = 0.5;
  // Evasive rule (0: off), last on the command: over evasive_horizon_s (rolled out
  // acceleration-limited from the current command) no walker's gap to the footprint may fall
  // below min(evasive_gap_m, the gap now) - walkers (tracks that move or moved once) predicted at
  // constant velocity but stopping where their own step would bring them closer than
  // walker_personal_space_m to the footprint (people keep their personal space; what closes it
  // further is the robot's motion). A command that would is replaced by the nearest (in speed
  // and turn) of a grid of commands that keeps every gap: slower along the same arc, turning,
  // sidestepping, and backing off at up to evasive_reverse_mps (0: never); the grid's obstacle
  // cells are kept as by the guard. When none keeps it, the one that leaves the largest
  // shortfall smallest. A velocity-obstacle choice over a short horizon.
  double evasive_gap_m = 0.0;
  double evasive_horizon_s = 1.0;
  double evasive_reverse_mps = 0.0;
  double walker_personal_space_m = 0.3;
  // Stopping-distance rule (0: off), last on the command: the robot must be able to stop short
  // of every walker. The command is held for stopping_reaction_s + stopping_margin_s (one
  // control period to react, and a margin), then the base brakes along the same arc at
  // stopping_deceleration_mps2 to a stop; every walker track (moving or moved once) is
  // predicted at its estimated velocity over that time. Wherever the footprint comes closer
  // than stopping_gap_m to a walker's disc (0.3 m plus the disc's offset from the body),
  // closer than standing still would leave it at the same instant, the command's speed is
  // scaled down (the same arc) to the largest fraction that keeps it: the robot brakes
  // proportionally, in time, instead of stopping hard once inside. Standing always passes
  // (turning in place does not move the circular footprint).
  double stopping_gap_m = 0.0;
  double stopping_deceleration_mps2 = 0.8;
  double stopping_reaction_s = 0.1;
  double stopping_margin_s = 0.1;
  // The rule only in the frames the guard replaces the command (slowing, stopping, swerving,
  // turning): false, in every frame.
  bool stopping_with_guard_only = false;
  // Walker bodies (0: off): no command, the wanted one or an alternative, may by the robot's own
  // motion over body_horizon_s bring the footprint closer than body_gap_m to a walker's body
  // (ObstacleTracker::BodyDisc: behind the cells the camera sees, at any speed, standing and
  // slow walkers included) than standing still would leave it at the same instant. Standing
  // and turning in place always pass, so a robot that cannot pass stops outside the band
  // instead of creeping into it.
  double body_gap_m = 0.0;
  double body_horizon_s = 1.0;
  // A command slower than body_creep_speed_mps (creeping) keeps body_creep_gap_m instead when
  // that is wider: in a stand-off the robot stops rather than creeps on (0: off).
  double body_creep_speed_mps = 0.0;
  double body_creep_gap_m = 0.4;
  // Every track counts as a body, also one never seen moving (a person standing since the
  // camera first saw it, or whose track was lost and found again; a pillar too). false: tracks
  // that move or moved once.
  bool body_all_tracks = false;
  // Own motion only: the moving walkers' predicted gap counts against a command only when, over
  // the horizon, the command's smallest gap is smaller than standing still would leave (the
  // robot's motion makes the approach closer). A walker that would come as close to a standing
  // robot (overtaking it from behind, walking at it from the side) does not make the guard
  // stop or swerve. For a robot that sees all round (a planar scanner): without it the guard
  // reacts to every walker overtaking it. false: every predicted gap counts.
  bool own_motion_only = false;
  // Approach speed near tracks (0: off), last on the command: for every walker track (moving or
  // moved once; every track with approach_all_tracks) whose disc lies within approach_near_m of
  // the footprint, the speed at which the command's own motion brings the footprint towards the
  // track's centre (v cos(bearing)) may not exceed approach_rate_per_s times the gap left above
  // approach_gap_m: the footprint slows as it nears a person and stops approaching at
  // approach_gap_m (a barrier on the gap; the turn is kept, moving away is free). A track's disc
  // is built from the cells the camera sees of a body, whose centre lies behind them: a gap a
  // little above the 0.3 m wanted from the body. Off: 0.35 m in the crowd benchmark held the
  // robot among the walkers (7/10, one contact, 0.236 m/s on seeds 101-110).
  double approach_gap_m = 0.0;
  double approach_rate_per_s = 2.0;
  double approach_near_m = 0.6;
  bool approach_all_tracks = false;
  // Remembered walkers (0: off; with walker_tracker.side_memory_s): no command, the wanted one
  // or an alternative, may by the robot's own motion over remembered_horizon_s bring the
  // footprint closer than remembered_gap_m to a remembered track's disc (one that left the
  // camera's view to the side, ObstacleTracker::RememberedDisc) within remembered_near_m of the
  // footprint, closer than standing still would leave it at the same instant: the robot does
  // not turn, swerve or drive into a walker it saw go beside it. Standing and turning in place
  // always pass.
  double remembered_gap_m = 0.0;
  double remembered_horizon_s = 1.0;
  double remembered_near_m = 1.5;
  // The rule only on the guard's alternatives (slowing, turning, swerving), not on the wanted
  // command: the guard does not swerve into a walker it saw go beside, and intervenes no more
  // often than without the rule.
  bool remembered_alternatives_only = false;
};

struct GuardResult {
  VelocityCommand command;
  bool intervened = false;       // the wanted command would have come too close to a walker
  bool kept_gap = true;          // the chosen command keeps min_gap_m over the horizon
  double predicted_gap_m = 0.0;  // of the chosen command (+infinity: no moving walker)
  std::string action;            // what the guard did ("slow", "stop", "back off", ...)
};

class CrowdGuard {
 public:
  explicit CrowdGuard(CrowdGuardOptions options = CrowdGuardOptions());

  // `current`: the command the base follows now; `wanted`: the controller's command.
  GuardResult Check(const Pose2D& pose, const VelocityCommand& current,
                    const VelocityCommand& wanted, double robot_radius_m,
                    const ObstacleGrid& grid, const ObstacleTracker& tracker) const;
  // The gap filter (gap_filter_m): `wanted` itself when it keeps the gap, else the same command
  // with the forward speed (then the turn) scaled down until it does; v = 0 always passes.
  VelocityCommand FilterGap(const Pose2D& pose, const VelocityCommand& wanted,
                            double robot_radius_m, const ObstacleTracker& tracker) const;
  // The blind-side speed (blind_side_speed_mps): `wanted` itself, or, near a walker out of
  // view, the same arc at the capped forward speed.
  VelocityCommand BlindSideSpeed(const Pose2D& pose, const VelocityCommand& wanted,
                                 double robot_radius_m, const ObstacleTracker& tracker) const;
  // The approach speed (approach_gap_m): `wanted` itself, or the same turn at the largest
  // forward speed whose approach towards every near track keeps to its barrier.
  VelocityCommand ApproachSpeed(const Pose2D& pose, const VelocityCommand& wanted,
                                double robot_radius_m, const ObstacleTracker& tracker) const;
  // The evasive rule (evasive_gap_m): `wanted` itself when it keeps every walker's gap, else
  // the nearest command of its grid that does (or falls least short).
  VelocityCommand Evade(const Pose2D& pose, const VelocityCommand& current,
                        const VelocityCommand& wanted, double robot_radius_m,
                        const ObstacleGrid& grid, const ObstacleTracker& tracker) const;
  // The stopping-distance rule (stopping_gap_m): `wanted` itself when the robot can stop short
  // of every walker from it, else the same arc at the largest speed that can (standing, when
  // none can). `current`: the command the base follows now (its speed when the rule acts).
  VelocityCommand BrakeToStopShort(const Pose2D& pose, const VelocityCommand& current,
                                   const VelocityCommand& wanted, double robot_radius_m,
                                   const ObstacleTracker& tracker) const;
  const CrowdGuardOptions& options() const { return options_; }

 private:
  struct Rollout {
    double gap_m = 0.0;         // smallest predicted gap to a walker
    bool static_ok = true;      // clear of the grid (or not closer than at the start)
    bool standing_ok = true;    // clear of standing walkers (CrowdGuardOptions::standing_walkers)
    bool body_ok = true;        // clear of the walkers' bodies (CrowdGuardOptions::body_gap_m)
    bool remembered_ok = true;  // clear of remembered walkers (CrowdGuardOptions::remembered_gap_m)
    bool Clear() const { return static_ok && standing_ok && body_ok && remembered_ok; }
    Pose2D end;
  };
  Rollout Roll(const Pose2D& pose, const VelocityCommand& current,
               const VelocityCommand& target, double robot_radius_m, const ObstacleGrid& grid,
               const ObstacleTracker& tracker) const;

  bool KeepsGap(const Pose2D& pose, const VelocityCommand& cmd, double robot_radius_m,
                const ObstacleTracker& tracker) const;
  // The evasive rule's rollout of `target`: the largest shortfall of a walker's gap below what
  // it must keep (<= 0: kept), or +infinity when it runs into the grid's cells.
  double EvasiveShortfall(const Pose2D& pose, const VelocityCommand& current,
                          const VelocityCommand& target, double robot_radius_m,
                          const ObstacleGrid& grid, const ObstacleTracker& tracker) const;

  // The stopping-distance rule's check of `cmd` (see BrakeToStopShort).
  bool StopsShort(const Pose2D& pose, const VelocityCommand& current, const VelocityCommand& cmd,
                  double robot_radius_m, const ObstacleTracker& tracker) const;

  CrowdGuardOptions options_;
};

}  // namespace icgm
