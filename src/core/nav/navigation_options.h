// Options of the navigation stack (config/navigation.yaml): one section per part.
//   navigator:      route following (eq. 6.5 pointer), replanning, goal and abort rules
//   obstacle_grid:  ObstacleGridOptions      local_planner: LocalPlannerOptions
//   controller:     TrackingOptions
//   walker_tracker: ObstacleTrackerOptions    crowd_guard: CrowdGuardOptions (walkers' predicted
//   motion)
// The footprint (robot_radius_m) is given once, in navigator:, and copied into the parts.
#pragma once

#include <string>

#include "core/common/option_reader.h"
#include "core/nav/crowd_guard.h"
#include "core/nav/local_planner.h"
#include "core/nav/obstacle_grid.h"
#include "core/nav/obstacle_tracker.h"
#include "core/nav/tracking_controller.h"

namespace icgm {

struct NavigatorOptions {
  double robot_radius_m = 0.25;
  // Reached (stop): the robot's centre this close to the goal. Tighter than the 0.25 m a goal
  // is judged by, so that the stop itself does not use up the whole bound.
  double goal_tolerance_m = 0.1;
  int omega = 3;                  // eq. 6.5: logical step (route nodes) of the pointer
  double lookahead_m = 1.2;       // the local goal is at least this far ahead on the route
  double route_spacing_m = 0.05;  // the route polyline is resampled this finely
  double replan_period_s = 0.25;  // OMPL at most this often (4 Hz) while avoiding
  double rejoin_check_m = 2.0;    // the route ahead is checked free this far
  // A blocked route is followed on (the safety stop guards it) this long before a detour is
  // planned. 0 (default): plan at once; 1 s was measured worse in the crowd (more contacts
  // with walkers, the robot closes in on them before turning away).
  double detour_delay_s = 0.0;
  double max_goal_off_map_m = 0.75;     // goal farther than this from every keyframe: off the map
  double max_localization_age_s = 2.0;  // no pose for longer: aborted
  double max_depth_age_s = 1.0;         // no depth for longer: aborted
  double goal_blocked_timeout_s =
      15.0;                       // goal inside an obstacle for longer: aborted (walkers linger)
  double pointer_search_m = 3.0;  // re-anchoring looks this far along the route from the pointer
  // No progress: the route left to drive has not shrunk by no_progress_m within this long (the
  // robot stood in a safety stop, waited or circled): aborted with what it was doing, as
  // move_base gives up after its patience, instead of a goal that never ends. 0: never. Longer
  // than any wait for walkers measured in the crowd benchmark (whose runs time out sooner).
  double no_progress_timeout_s = 60.0;
  double no_progress_m = 0.25;
  // After an avoidance manoeuvre the robot is rejoining the route until its localized base is
  // back within this distance of it (NavigationStatus::rejoining).
  double rejoin_tolerance_m = 0.05;
  // ... and its heading within this of the route's direction: a robot crossing the route at an
  // angle has not rejoined it yet. 0: off (the cross-track alone). On at 0.15 rad with the
  // Dubins rejoin (rejoin_dubins_radius_m), which follows the route back while rejoining: in
  // the crowd benchmark 10/10, 0 contacts, 0.305 m/s, outside avoidance mean 13 / max 77 mm
  // (before 17 / 101 mm; the rule alone, which changes no drive, only the label: 15 / 78 mm).
  // With the merge curve at 1 m, 0.15 rad was measured no better than the merge alone (8/10,
  // one contact, 168 mm).
  double rejoin_heading_rad = 0.15;
  // ... and its commanded turn rate within this: a robot still turning out of the rejoin curve
  // (it crosses the route and swings on while its turn rate unwinds at the angular-acceleration
  // limit) has not rejoined it yet; the rejoin (its Dubins curve, which first brings the turn
  // rate to zero) goes on. 0: off (0.2 rad/s in the crowd benchmark: 10/10 and 73 mm max outside
  // avoidance on seeds 101-110, but 7/10 on 111-120).
  double rejoin_turn_radps = 0.0;
  // Merge: while rejoining (and whenever the base is farther than rejoin_tolerance_m from a free
  // route), the tracked path is a curve from the robot's pose onto the route instead of the route
  // itself: the route offset along its normal by a cubic d(s) that starts at the robot's signed
  // offset with its heading (d(0) = e, d'(0) = tan of the heading error) and ends on the route,
  // tangent to it, this far ahead (d(D) = d'(D) = 0; at most the route left). Pure pursuit on it
  // steers with fixed gains on offset and heading (curvature about -6e/D^2 - 4 tan(psi)/D, damping
  // 0.8) whatever its speed-dependent lookahead, so the robot arrives along the route instead of
  // crossing it at an angle. Not used with a heading error beyond controller.turn_in_place_rad,
  // while heading away from the route (the carrot on the route turns the robot back first) or
  // when the curve is not free. 0: off (the route itself, the carrot pulls straight onto it).
  // Measured worse at 1 m in the crowd benchmark (8/10 reached, 0.279 m/s, 166 mm max outside
  // avoidance against 116 mm): a robot already close to the route and approaching it steeply
  // (after the detour's own steep join) gets a curve that must swing through the route, since
  // it starts along the heading; in a hand-built rejoin it halves the swing (5.3 -> 2.5 cm).
  double merge_distance_m = 0.0;
  // Goal stop along the route's line: within goal_tolerance_m of the goal the robot is reached
  // only once its localized base is also within this of the route. Until then it drives on
  // towards the goal point, which lies on the line. (Also "or abreast of the goal" was tried:
  // a steep arrival then stopped 8 cm off the line.) 0: off (reached anywhere within
  // goal_tolerance_m). On at 0.05 m (the rejoin tolerance): in the crowd benchmark the largest
  // deviation outside avoidance went 116 -> 101 mm (the goal frames of seeds 101 and 102: 71 ->
  // 50 and 116 -> 78 mm), 10/10 reached, 0.311 m/s, the other runs unchanged. 0.02 m since:
  // on seeds 101-120 only three goal stops change (goal errors 0.087 -> 0.054, 0.093 -> 0.064,
  // 0.093 -> 0.060 m), every other line of both benchmarks identical.
  double goal_line_tolerance_m = 0.02;
  // The tracked path goes on straight beyond the goal this far (the route's last direction), so
  // that the controller's carrot stays on the goal's line instead of the goal point pulling the
  // robot in at an angle; the robot brakes to stop 3 cm past the goal (abreast of it). 0: off
  // (the path ends at the goal). With the line rule, at 1 m, the crowd benchmark is unchanged in
  // its maximum outside avoidance (101 mm), 10/10, 0.308 m/s: not better.
  double goal_extension_m = 0.0;
  // The goal's orientation (move_base's yaw_goal_tolerance, 0.05 rad): once within the
  // position rule (goal_tolerance_m), the robot turns in place towards the goal's yaw, with the
  // controller's angular speed and acceleration limits and no translation, and the goal is
  // reached only when its heading is within this of the goal's yaw. 0: orientation ignored
  // (the goal is reached at its position, whatever the heading), as for goals given without a
  // meaningful orientation; a goal given without a yaw (SetGoal's goal_yaw_rad empty) ignores
  // it too.
  double goal_yaw_tolerance_rad = 0.05;
  // Detour join: an OMPL detour ends where it meets the route, often at an angle (its last
  // simplified segment), and pure pursuit then swings through the route. With this on, the
  // detour's end is replaced by a curve that leaves the detour tangentially and runs onto the
  // route tangentially this far (along the route) from where it leaves: the route offset along
  // its normal by a cubic d(s) with the detour's offset and slope at its start and d = d' = 0
  // at its end; it starts a third of this before the junction (so that it need not cross the
  // route). Kept only when the curve is free (the grid's inflation); else the detour as
  // planned. When the route is free again the robot still follows this end while it is on the
  // path and the path ahead comes no farther from the route than it is. 0: off. In a hand-built
  // detour it halves the swing through the route and the heading error after the rejoin; in
  // the crowd benchmark at 1 m (with the line rule) it is worse: 9/10 reached (seed 108's start
  // stall times out), 0.293 m/s, 111 mm max outside avoidance.
  double detour_join_m = 0.0;
  // Rejoin planned with a heading constraint: while rejoining (and whenever the base is farther
  // than rejoin_tolerance_m from a free route) the tracked path is a Dubins curve with this
  // turning radius onto the route (core/nav/dubins_rejoin.h): it starts where the robot's
  // present turn rate has been brought to zero at the angular-acceleration limit, and ends on a
  // route point 0.3-2.0 m ahead with the route's direction; of those join points the free curve
  // that stays nearest the route is kept (then the shorter one). Not used with a heading error
  // beyond controller.turn_in_place_rad (the controller turns in place first). 0: off. On at
  // 0.1 m with rejoin_heading_rad 0.15 (see there); alone (the rejoin ends at the cross-track)
  // it was worse in the crowd benchmark: 9/10, one contact, 117 mm max outside avoidance.
  double rejoin_dubins_radius_m = 0.1;
  // The rejoining status (the end of the avoidance manoeuvre, NavigationStatus::rejoining)
  // lasts at most this long after the last avoiding frame, whatever the cross-track and heading:
  // a rejoin counts as part of the manoeuvre only while it is bounded in time. The navigator's
  // own use of the rejoin (the merge and Dubins curves) is not bounded by it. 0: no bound. 4 s:
  // beyond the longest rejoin measured in the crowd benchmark (2.8 s, 1.7 m driven), so it
  // changes none of its frames, but no rejoin can count as manoeuvre for longer.
  double rejoin_max_s = 4.0;
  // Rejoin speed: until the robot is back on the route by the rejoin rule (its localized base
  // within rejoin_tolerance_m of the route and heading within rejoin_heading_rad of it), outside
  // a detour, the controller's top speed is capped at this. Pure pursuit's swing through the
  // route after an angled approach grows with the approach angle times the lookahead (about
  // psi * L / sqrt(2) before damping), and the lookahead grows with the speed
  // (controller.lookahead_time_s): a slower approach turns onto the route sooner. 0: off.
  double rejoin_speed_mps = 0.0;
  // Approach speed (0: off): outside a detour the top speed is capped so that, at its heading
  // error against the route psi, the robot can turn parallel to the route before it overshoots
  // it by more than this. Turning at approach_turn_radps from speed v takes the base
  // v (1 - cos psi) / w sideways: heading towards the route, the room is the offset plus this,
  // so v <= w room / (1 - cos psi), not below approach_min_speed_mps. Heading away it does not
  // act (with the margin alone as room it held the robot at creeping speed among the walkers:
  // 3 of the first 7 crowd seeds reached). On the route with a small
  // heading error it does not bind (0.1 rad, 3 cm: 3 m/s); it slows the angled crossings after
  // a swerve or a rejoin curve, where pure pursuit's swing grows with the speed.
  double approach_overshoot_m = 0.0;
  double approach_turn_radps = 0.5;
  double approach_min_speed_mps = 0.2;
  // Stale localization (0: off): between localization fixes the pose runs on odometry and its
  // error grows with the distance driven; the next fix moves the estimate at once, and the
  // robot swings through the route after the jump. Outside a detour, once more than
  // stale_fix_distance_m has been driven (as localized) since the last fix, the top speed is
  // capped, falling linearly from the controller's top speed to stale_fix_speed_mps at twice
  // that distance and held there until the next fix (StaleFixSpeedCap).
  double stale_fix_distance_m = 0.0;
  double stale_fix_speed_mps = 0.4;
  // Where the controller's lateral error law (controller.lateral_rate_per_s > 0) steers, while
  // the tracked path is the route itself (not a detour): false, only until the robot is back on
  // the route by the rejoin rule (rejoining after an avoidance, or off it by more than
  // rejoin_tolerance_m or rejoin_heading_rad, e.g. after a guard's turn); the law then tracks
  // the route directly (no merge or Dubins curve). true: all along the route.
  bool lateral_law_on_route = false;
  // Narrower scopes of the law (each off: as above). lateral_law_after_avoidance: not before
  // the route's first avoidance (the start, where the robot's heading differs from the route's
  // first direction, is left to pure pursuit). lateral_law_rejoin_only: only while the
  // rejoining status is raised (after an avoidance, until back on the route, at most
  // rejoin_max_s after the last avoiding frame); then pure pursuit again.
  bool lateral_law_after_avoidance = false;
  bool lateral_law_rejoin_only = false;
  // Detours keep out of the area the moving walkers (ObstacleTracker) will sweep over this
  // horizon: their predicted discs, one every walker_sweep_step_s, are obstacles for the local
  // planner (and the choice of its goal); when no detour is found that way, the planner tries
  // again on the grid alone. 0: off (the planner sees only the grid).
  double walker_sweep_s = 0.0;
  double walker_sweep_step_s = 0.25;
  // An occupied goal: an obstacle (people standing there) closer to it than the grid's
  // inflation, so that the footprint cannot stand on it with the clearance. The robot then
  // heads for the free point nearest the goal within this distance and is reached there (the
  // reason says the goal was occupied). 0: off (it waits for the goal to clear).
  double goal_occupied_tolerance_m = 0.0;
  // The robot stood this long (in total) waiting on the goal while it stayed occupied (reset
  // when it clears): aborted ("goal ... occupied"), the robot stopped where it is, instead of
  // waiting for its user's timeout. 0: off (waits as long as the goal is occupied).
  double goal_occupied_timeout_s = 0.0;
  // A planar scan (Navigator::UpdateScan) feeds the walker tracker only: its returns join the
  // depth's fresh obstacle cells for the tracker (and so the crowd guard), but the obstacle
  // grid (detours, the safety stop) stays the camera's. false: the grid takes the scan too.
  bool scan_tracker_only = false;
  // Walker cells beside and behind the robot left out of the path checks: for the route check,
  // the detour's checks and the local planner (not the controller's safety stop nor the crowd
  // guard), the obstacle cells of walker tracks (ObstacleTracker::IsWalker, within their radius
  // plus walker_cell_margin_m of where they were last seen) that lie within
  // walker_cells_near_m of the robot's centre and not ahead of its footprint's front (along its
  // heading) are dropped: a walker beside or behind the robot (e.g. seen by a planar scanner)
  // does not block the corridor ahead. false: every cell counts. With a planar scanner,
  // crowd_guard.own_motion_only and forget_walker_trail, crowd benchmark seeds 101-110 and
  // 111-120: 9/10 and 9/10, 0 contacts, 22 and 26 close passes (7/10 and 7/10 without the two
  // options), but 122 / 110 mm outside avoidance; without the scanner 3 contacts with walkers
  // beside the robot (the camera no longer sees them).
  bool walker_cells_ahead_only = false;
  double walker_cells_near_m = 1.5;
  double walker_cell_margin_m = 0.1;
  // Walker trails forgotten: the grid's memory cells a walker track marked (the fresh cells
  // within its radius plus walker_cell_margin_m) are cleared once that walker is seen elsewhere
  // (tracked in a later frame without those cells), instead of staying memory_s where it
  // walked. false: the grid's memory alone.
  bool forget_walker_trail = false;
  // Walker bodies in the grid: every walker track (ObstacleTracker::IsWalker: moving, or
  // standing or creeping after it moved once) enters the grid the robot drives by as its body
  // disc (ObstacleTracker::BodyDisc now: at least walker_tracker.body_radius_m wide, centred
  // walker_tracker.body_offset_m behind the cells the camera sees), so that the grid's inflation
  // (robot radius + obstacle_grid.clearance_m) is kept from the body, not from the front of it
  // the camera sees (which lies inside the body). The route check, the detours (local planner),
  // the controller's safety stop and clear speed, and the crowd guard's grid check all use it:
  // before a standing person in its way the robot stops outside the clearance and plans around
  // the body instead of creeping past it. The goal checks keep the grid itself. false: off.
  bool walker_bodies_in_grid = false;
  // ... also for the route check, the detours and the rejoin curves; false: the bodies are for
  // the controller and the crowd guard only (stop short of a standing person and do not creep
  // or swerve into one), the paths are checked and planned on the grid itself.
  bool walker_bodies_path_checks = true;
  // Path checks keep the inflation: the route check ahead, the detours' and the rejoin curves'
  // checks (LocalPlanner::SegmentFree) let the bare footprint suffice (a robot already inside
  // the inflation escaping) only within local_planner.start_escape_m of the robot. false: each
  // piece of the path is checked with the escape measured from its own start, and the pieces are
  // 5 cm long, so a path counts as free wherever the bare footprint fits: the route is followed
  // past a person standing beside it with the footprint up to touching the cells seen of them,
  // and only the crowd guard (moving walkers) and the safety stop (ahead) keep a gap.
  bool path_checks_inflated = false;
  // ... for the route check ahead only: the detours (planned with the clearance) and the rejoin
  // curves are re-checked as without it, so that a walker coming near a detour does not make
  // the robot replan at once.
  bool path_checks_inflated_route_only = false;
  // ... the clearance those checks keep beyond the footprint (from the cells), between the bare
  // footprint (0) and the grid's (obstacle_grid.clearance_m, 0.3 m): a narrower check blocks
  // the route less often beside a standing person. Negative: the grid's clearance.
  double path_check_clearance_m = -1.0;
  // Stall fallback: when the robot has stood blocked (the route check ahead and every detour
  // refused: no detour, or waiting to plan) this long, the path checks drop back to the bare
  // footprint (escape measured from each piece's start, as with path_checks_inflated false) for
  // path_checks_relax_for_s, so that a robot boxed in by the clearance squeezes past at a
  // smaller clearance instead of waiting. 0: off.
  double path_checks_relax_after_s = 0.0;
  double path_checks_relax_for_s = 3.0;
  // ... and the detours planned meanwhile keep this clearance beyond the footprint instead of
  // the grid's (negative: the grid's). The stall is timed whether or not path_checks_inflated
  // is on: without it only the planner's clearance changes (a detour fallback).
  double path_checks_relax_plan_clearance_m = -1.0;
};

struct NavigationOptions {
  NavigatorOptions navigator;
  ObstacleGridOptions obstacle_grid;
  LocalPlannerOptions local_planner;
  TrackingOptions controller;
  ObstacleTrackerOptions tracker;
  CrowdGuardOptions guard;
};

// Reads the six sections (absent ones keep their defaults), range-checks every key, rejects
// unknown keys and copies navigator.robot_radius_m into the parts. Throws LoadError.
void ReadNavigationOptions(const OptionReader& reader, NavigationOptions* options);
NavigationOptions LoadNavigationOptions(const std::string& path);

}  // namespace icgm
