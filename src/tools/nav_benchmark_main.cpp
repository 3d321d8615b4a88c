// icgm_nav_benchmark: the robot must drive. A teach run maps the start of the scenario's route
// (SlamSystem in mapping mode on the fixed-route simulator, crowd included); then N repeat runs
// in closed loop, each with another crowd: every frame is rendered, localized on the learned map
// (SlamSystem in localization mode: front end + relocalization), turned into an obstacle grid
// and a velocity command by the Navigator, and the ClosedLoopSimulator executes the command.
// Prints one line per run and a summary; writes a plot per run (route, path driven, walkers,
// deviation over time). Deviation is the true base_link's distance from the route where it truly
// lies: the teach run's true base positions at the route's keyframes. Frame times are the
// thread's CPU time for localization + obstacle grid + navigation (rendering excluded; wall
// times printed beside them).
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <deque>
#include <filesystem>
#include <limits>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include <opencv2/imgcodecs.hpp>
#include <opencv2/core/utility.hpp>
#include <opencv2/imgproc.hpp>

#include "core/common/progress_bar.h"
#include "core/common/sample_summary.h"
#include "core/common/thread_cpu_time.h"
#include "core/eval/plot_axes.h"
#include "core/nav/navigator.h"
#include "core/sim/close_pass_escape.h"
#include "core/sim/close_pass_log.h"
#include "core/sim/closed_loop_simulator.h"
#include "core/sim/simulator.h"
#include "core/slam/slam_system.h"
#include "tools/cli_args.h"

namespace {

using namespace icgm;

constexpr char kUsage[] =
    "usage: icgm_nav_benchmark [--config config/sim/nav_cafeteria.yaml]\n"
    "                          [--nav-config config/navigation.yaml] [--slam-config DIR]\n"
    "                          [--runs 10] [--route-m 12] [--first-crowd-seed 101]\n"
    "                          [--out out/nav] [--timeout-factor 3] [--trace-fixes]\n"
    "                          [--trace-deviation] [--classify-close-passes] [--scanner]\n"
    "  Teach run: maps the first --route-m metres of the scenario's route (plus 1.5 m).\n"
    "  Repeat runs: closed loop from the route's start to the goal --route-m ahead, crowd seeds\n"
    "  first-crowd-seed .. +runs-1; a run that takes longer than timeout-factor x the route at\n"
    "  the controller's top speed has failed. Plots: OUT/run_<k>.png.\n"
    "  The goal is the taught place: where the teach run was after --route-m metres, given in\n"
    "  MAP coordinates (the teach map's estimate of that frame's base, as a goal clicked on the\n"
    "  map); a run reached it when the navigator stopped there (reached state) with the robot's\n"
    "  true centre within 0.25 m of that place's true position during the teach run (the\n"
    "  navigator stops within its own navigator.goal_tolerance_m of the goal in the map), and,\n"
    "  unless navigator.goal_yaw_tolerance_rad is 0, with its true heading within 0.2 rad of\n"
    "  the teach run's there: the goal's yaw is the teach map's heading of that frame's base.\n"
    "  The final turn in place at the goal is reported apart (time, heading error); time, speed\n"
    "  and deviation figures end where the turn begins.\n"
    "  Per run and overall, outside avoidance manoeuvres (neither avoiding nor rejoining) the\n"
    "  true deviation, the deviation as localized (the estimate's distance from the route in\n"
    "  the map) and the localization error against the map, apart from the deviation in\n"
    "  avoidance manoeuvres; how long the rejoins (counted as manoeuvre) last; fixes per\n"
    "  keyframe, the error before and after them, and why the other keyframes gave none.\n"
    "  --trace-fixes: one line per localization keyframe on stderr (correction, error to the\n"
    "  world and to the map before and after, the keyframes registered; or why no fix).\n"
    "  --trace-deviation: one line per frame on stderr (true deviation, deviation as localized,\n"
    "  localization error against the map, state, avoiding/rejoining, command, fix).\n"
    "  --classify-close-passes: for every close pass, where the walker came from (front, side,\n"
    "  behind; yielding or not; its speed) and whether the robot could have kept 0.3 m: from\n"
    "  the simulator's state 0.1-1.5 s before the pass began, brake, turn in place, keep going,\n"
    "  sidestep (forward-only) or back off (reversing), each held, then stand, driven with the\n"
    "  true crowd (ground truth; an oracle); the latest such moment is printed per pass.\n"
    "  --scanner: the robot's planar scanner on (the scenario's scanner: section, enabled or\n"
    "  not): each frame's scan joins the depth in the obstacle grid and the walker tracker.";
constexpr tools::ToolInfo kTool{"icgm_nav_benchmark", kUsage};

struct RunResult {
  int crowd_seed = 0;
  bool reached = false;
  std::string end;  // final state and reason
  double goal_error_m = 0.0;
  double time_s = 0.0;  // until the goal's position was reached (the final turn apart)
  double distance_m = 0.0;
  // The final turn in place to the goal's yaw (navigator.goal_yaw_tolerance_rad), and the true
  // heading at the end minus the teach run's at the goal.
  double final_turn_s = 0.0;
  double yaw_error_rad = 0.0;
  // The true centre's displacement during the turn (commanded none: the base braking from its
  // speed when the position was reached, which a run ending there did not count).
  double turn_drift_m = 0.0;
  // Outside avoidance: neither avoiding nor rejoining the route (the navigator's own account);
  // _3s: the earlier measure, not avoiding for 3 s.
  std::vector<double> deviation_m, deviation_outside_m, deviation_outside_3s_m;
  int collisions = 0;
  double min_clearance_m = 0.0;
  int avoid_frames = 0, stop_frames = 0, plans = 0, yield_frames = 0, time_cap_hits = 0;
  int gap_filter_frames = 0;
  int blind_side_frames = 0;
  int approach_frames = 0;
  int evasive_frames = 0;
  int stopping_frames = 0;
  int stale_fix_frames = 0;
  int relaxed_frames = 0;  // navigator.path_checks_relax_after_s relaxed the path checks
  long state_checks = 0;
  Eigen::Vector2d end_pose = Eigen::Vector2d::Zero();
  std::string contacts;  // each contact with a walker: time, bearing, what the robot did
  size_t relocalizations = 0;
  std::vector<double> frame_ms, frame_wall_ms, frame_with_render_ms;
  int static_collisions = 0, pedestrian_collisions = 0;
  // Episodes with a walker closer than kTargetClearanceM to the footprint (who closed the gap,
  // what the robot did), and the closest.
  std::vector<sim::ClosePass> close_passes;
  // --classify-close-passes: one per close pass, same order.
  struct Escape {
    std::string sector;  // where the walker was when the pass began: front / side / behind
    bool walker_yields = true;
    double walker_speed_mps = 0.0;
    double walker_closing_mps = 0.0;  // its speed towards the robot (negative: away)
    // The latest lead (s before the pass began) from which a forward-only escape / any escape
    // (reversing allowed) kept the clearance, and its name; < 0: none within the leads tried.
    double forward_lead_s = -1.0, any_lead_s = -1.0;
    std::string forward_plan, any_plan;
    double track_gap_m = 0.0;  // the navigator's nearest walker track then (footprint gap)
  };
  std::vector<Escape> escapes;
  // One per close pass, same order: what the navigator perceived of the walker in the step
  // its gap fell below the clearance (PerceivePass).
  struct Perception {
    double bearing_rad = 0.0;     // the walker from the robot's heading
    bool in_view = false;         // within the camera's field of view and depth range
    int track = -1;               // the navigator's track nearest the walker's true centre (-1: none)
    bool track_walker = false;    // it moves or moved once (the walker rules count it)
    bool track_moving = false;    // it moves now (the crowd guard's rollouts count it)
    bool track_remembered = false;  // out of the camera's view, remembered (side memory)
    double track_age_s = 0.0;     // since the track was last seen
    double track_error_m = 0.0;   // its centre from the walker's true centre
    double track_gap_m = 0.0;     // its disc from the footprint (localized)
    double true_speed_mps = 0.0, track_speed_mps = 0.0;
    double velocity_error_mps = 0.0;  // |estimated - true velocity|: the prediction's error rate
    double command_v = 0.0, command_w = 0.0;
    std::string action;           // state and guard action
  };
  std::vector<Perception> perceptions;
  double min_walker_clearance_m = 1e9;
  // Localization: distance between the localized base (in the world through the teach map's
  // start) and the true one, every frame, and the size of each fix's correction.
  // _map: against the map itself: the true base placed through the nearest keyframe
  // (its map pose times the true motion from where the teach run took it).
  std::vector<double> localization_error_m, localization_error_map_m, fix_jump_m;
  // Outside avoidance (the frames of deviation_outside_m): the localization error against the
  // map, and the deviation as the robot believes it (its estimate's distance from the route in
  // the map); the true deviation differs from the believed one by at most the localization error.
  std::vector<double> localization_error_outside_m, believed_deviation_outside_m;
  std::vector<double> deviation_avoidance_m;  // the other frames: avoiding or rejoining
  // Each rejoin (the frames from the end of an avoidance until the navigator's rejoining flag
  // drops): its duration, the true distance driven in it and the largest true deviation in it.
  std::vector<double> rejoin_s, rejoin_m, rejoin_deviation_m;
  // The frame of the largest deviation outside avoidance: when and what the robot did there.
  std::string worst_outside;
  // Localization error against the map just before and just after each fix.
  std::vector<double> error_before_fix_m, error_after_fix_m;
  int localization_keyframes = 0;  // front-end keyframes located in the map (fixes or not)
  std::map<std::string, int> no_fix_reasons;
  // Frames the robot was commanded to stand (|v| < kStandingMps), by cause (StandingCause).
  std::map<std::string, int> standing_frames;
  double mean_speed() const { return time_s > 0 ? distance_m / time_s : 0.0; }
};

using icgm::ThreadCpuMs;

// The clearance between the footprint and a walker the navigation must keep (contacts are
// counted at 0, close passes below this, less 1 mm: non-yielding walkers keep exactly
// personal_space_m = 0.3 m, in float coordinates).
constexpr double kTargetClearanceM = 0.3;
constexpr double kClearanceToleranceM = 1e-3;
// Success: the true end this close to the taught place's true position (independent of the
// navigator's stopping tolerance, which may be tighter).
constexpr double kSuccessToleranceM = 0.25;
// ... and, when the goal's orientation is driven to, the true heading this close to the teach
// run's there (the navigator turns to within navigator.goal_yaw_tolerance_rad in the map).
constexpr double kSuccessYawRad = 0.2;

double PointPolylineDistance(const Eigen::Vector2d& p, const std::vector<Eigen::Vector2d>& line) {
  double best = line.empty() ? 0.0 : (line[0] - p).norm();
  for (size_t i = 1; i < line.size(); ++i) {
    const Eigen::Vector2d ab = line[i] - line[i - 1];
    const double len2 = ab.squaredNorm();
    const double s = len2 > 0 ? std::clamp((p - line[i - 1]).dot(ab) / len2, 0.0, 1.0) : 0.0;
    best = std::min(best, (line[i - 1] + s * ab - p).norm());
  }
  return best;
}

// Below this commanded speed a frame counts as standing.
constexpr double kStandingMps = 0.05;

std::vector<Eigen::Vector2d> WalkerPositions(const sim::ClosedLoopSimulator& sim) {
  std::vector<Eigen::Vector2d> out;
  for (const auto& p : sim.pedestrians()) out.emplace_back(p.x_m, p.y_m);
  return out;
}

std::string ClosePassList(const std::vector<sim::ClosePass>& passes) {
  std::string out;
  for (const auto& c : passes) {
    char line[384];
    std::snprintf(line, sizeof(line),
                  " [t %.1f s, %.3f m at %.1f s, v %.2f m/s, %.2f / %.2f m, below: %.3f / %.3f m, "
                  "%s]",
                  c.start_s, c.min_clearance_m, c.min_at_s, c.robot_speed_mps, c.robot_closed_m,
                  c.walker_closed_m, c.robot_inside_m, c.walker_inside_m, c.context.c_str());
    out += line;
  }
  return out;
}

// What the navigator perceived of walker `j` after the step from `walkers_before`: its bearing
// and whether the camera could see it (field of view and depth range; occlusion not checked),
// the track nearest its true centre (map frame; within the walker's radius + 0.3 m), and the
// command of that step.
RunResult::Perception PerceivePass(size_t j, const sim::ClosedLoopSimulator& sim,
                                   const std::vector<Eigen::Vector2d>& walkers_before,
                                   const Navigator& nav, const NavigationStatus& status,
                                   const Pose3& map_from_world, double max_range_m, double dt) {
  RunResult::Perception out;
  const sim::PlanarPose& r = sim.planar_pose();
  const auto people = sim.pedestrians();
  const Eigen::Vector2d walker(people[j].x_m, people[j].y_m);
  const Eigen::Vector2d d = walker - Eigen::Vector2d(r.x_m, r.y_m);
  out.bearing_rad = WrapAngleRad(std::atan2(d.y(), d.x()) - r.yaw_rad);
  const CameraIntrinsics& K = sim.intrinsics();
  const double half_fov = std::atan2(0.5 * K.width_px, K.fx_px);
  out.in_view = std::abs(out.bearing_rad) <= half_fov && d.norm() <= max_range_m;
  const Eigen::Vector2d true_velocity = (walker - walkers_before[j]) / dt;
  out.true_speed_mps = true_velocity.norm();
  const Eigen::Matrix3d R = map_from_world.rotation();
  const Eigen::Vector2d walker_map =
      (map_from_world * Eigen::Vector3d(walker.x(), walker.y(), 0.0)).head<2>();
  const Eigen::Vector2d velocity_map =
      (R * Eigen::Vector3d(true_velocity.x(), true_velocity.y(), 0.0)).head<2>();
  const double gate = sim.pedestrian_radius_m(j) + 0.3;
  double best = gate;
  for (const TrackedObstacle& t : nav.tracker().tracks()) {
    const double e = (nav.tracker().Predict(t, 0.0) - walker_map).norm();
    if (e >= best) continue;
    best = e;
    out.track = t.id;
    out.track_walker = ObstacleTracker::IsWalker(t);
    out.track_moving = t.moving;
    out.track_remembered = t.remembered;
    out.track_age_s = DurationSeconds(nav.tracker().last_update(), t.last_seen);
    out.track_error_m = e;
    out.track_speed_mps = t.velocity_mps.norm();
    out.velocity_error_mps = (t.velocity_mps - velocity_map).norm();
    if (nav.pose()) {
      out.track_gap_m = (nav.pose()->position() - nav.tracker().Predict(t, 0.0)).norm() -
                        t.radius_m - nav.options().navigator.robot_radius_m;
    }
  }
  out.command_v = status.command.linear_mps;
  out.command_w = status.command.angular_radps;
  out.action = std::string(NavigationStateName(status.state)) +
               (status.yielding ? ", guard " + status.guard_action : "") +
               (status.avoiding ? ", avoiding" : "") + (status.rejoining ? ", rejoining" : "");
  return out;
}

std::string PerceptionList(const std::vector<RunResult::Perception>& list) {
  std::string out;
  for (const auto& p : list) {
    char line[320];
    if (p.track < 0) {
      std::snprintf(line, sizeof(line), " [%.0f deg %s, no track, true %.2f m/s; cmd %.2f m/s %.2f rad/s, %s]",
                    p.bearing_rad * 180.0 / M_PI, p.in_view ? "in view" : "out of view",
                    p.true_speed_mps, p.command_v, p.command_w, p.action.c_str());
    } else {
      std::snprintf(line, sizeof(line),
                    " [%.0f deg %s, track %d %s seen %.1f s ago, off %.2f m, gap %.2f m, speed "
                    "%.2f (true %.2f, error %.2f) m/s; cmd %.2f m/s %.2f rad/s, %s]",
                    p.bearing_rad * 180.0 / M_PI, p.in_view ? "in view" : "out of view", p.track,
                    p.track_remembered ? "remembered"
                    : p.track_moving   ? "moving"
                    : p.track_walker   ? "walker standing"
                                       : "never moved",
                    p.track_age_s, p.track_error_m, p.track_gap_m, p.track_speed_mps,
                    p.true_speed_mps, p.velocity_error_mps, p.command_v, p.command_w,
                    p.action.c_str());
    }
    out += line;
  }
  return out;
}

// Why the navigator commands the robot to stand: the safety stop's or the blocked route's
// reason in short, or the crowd guard's action.
std::string StandingCause(const NavigationStatus& s) {
  const auto has = [&](const char* text) { return s.reason.find(text) != std::string::npos; };
  if (s.state == NavigationState::kSafetyStop) {
    if (has("ahead of the footprint")) return "obstacle ahead";
    if (has("waiting to plan again")) return "waiting to plan";
    if (has("inflation")) return "detour goal blocked";
    if (has("footprint touches")) return "footprint in inflation";
    if (has("no path")) return "no detour";
    return "other stop";
  }
  if (s.yielding) return "guard " + s.guard_action;
  if (s.gap_filtered) return "gap filter";
  if (s.blind_side_slowed) return "blind side";
  if (s.approach_slowed) return "approach speed";
  if (s.evaded) return "evasive";
  if (s.stopping_braked) return "stopping distance";
  if (s.state == NavigationState::kActive) return "active (turning or starting)";
  return NavigationStateName(s.state);
}

std::string CauseList(const std::map<std::string, int>& counts) {
  std::string out;
  for (const auto& [cause, n] : counts) {
    out += (out.empty() ? "" : ", ") + cause + " " + std::to_string(n);
  }
  return out.empty() ? "none" : out;
}

double Mean(const std::vector<double>& v) {
  double s = 0.0;
  for (double x : v) s += x;
  return v.empty() ? 0.0 : s / v.size();
}
double Max(const std::vector<double>& v) {
  return v.empty() ? 0.0 : *std::max_element(v.begin(), v.end());
}
double Percentile(std::vector<double> v, double q) {
  if (v.empty()) return 0.0;
  std::sort(v.begin(), v.end());
  return v[std::min(v.size() - 1, static_cast<size_t>(q * (v.size() - 1) + 0.5))];
}

// --classify-close-passes: the pass that began in the step just taken (`sim` after it,
// `walkers_before` before it); `history` holds the simulator before each of the last steps
// (the last: before this one) and `track_gaps` the navigator's nearest walker track then.
RunResult::Escape ClassifyClosePass(const sim::ClosePass& pass, const sim::ClosedLoopSimulator& sim,
                                    const std::vector<Eigen::Vector2d>& walkers_before,
                                    const std::deque<sim::ClosedLoopSimulator>& history,
                                    const std::deque<double>& track_gaps,
                                    const sim::EscapeOptions& options, double dt) {
  RunResult::Escape e;
  const sim::PlanarPose& r = sim.planar_pose();
  const auto people = sim.pedestrians();
  const Eigen::Vector2d robot(r.x_m, r.y_m);
  const Eigen::Vector2d walker(people[pass.walker].x_m, people[pass.walker].y_m);
  const double bearing = std::abs(
      WrapAngleRad(std::atan2(walker.y() - robot.y(), walker.x() - robot.x()) - r.yaw_rad));
  e.sector = bearing < M_PI / 4 ? "front" : bearing < 3 * M_PI / 4 ? "side" : "behind";
  e.walker_yields = sim.pedestrian_yields(pass.walker);
  const Eigen::Vector2d velocity = (walker - walkers_before[pass.walker]) / dt;
  e.walker_speed_mps = velocity.norm();
  const Eigen::Vector2d to_robot = robot - walker;
  e.walker_closing_mps = to_robot.norm() > 1e-9 ? velocity.dot(to_robot.normalized()) : 0.0;
  for (size_t lead = 1; lead <= history.size(); ++lead) {
    const sim::ClosedLoopSimulator& start = history[history.size() - lead];
    const std::vector<sim::EscapePlan> plans =
        sim::EscapePlans(options, start.true_velocity().linear_mps);
    const double lead_s = lead * dt;
    if (e.any_lead_s < 0.0) {
      const int any = sim::FindEscape(start, plans, true, lead_s, options);
      if (any >= 0) e.any_lead_s = lead_s, e.any_plan = plans[any].name;
    }
    if (e.forward_lead_s < 0.0) {
      const int forward = sim::FindEscape(start, plans, false, lead_s, options);
      if (forward >= 0) {
        e.forward_lead_s = lead_s, e.forward_plan = plans[forward].name;
        e.track_gap_m = track_gaps.size() >= lead ? track_gaps[track_gaps.size() - lead] : 0.0;
      }
    }
    if (e.any_lead_s >= 0.0 && e.forward_lead_s >= 0.0) break;
  }
  return e;
}

std::string EscapeList(const std::vector<RunResult::Escape>& escapes) {
  std::string out;
  for (const auto& e : escapes) {
    char line[320];
    const auto lead = [](double s, const std::string& plan) {
      char t[96];
      if (s < 0.0) return std::string("none");
      std::snprintf(t, sizeof(t), "%.1f s (%s)", s, plan.c_str());
      return std::string(t);
    };
    std::snprintf(line, sizeof(line), " [%s, %s, %.2f m/s, closing %.2f m/s; %s; %s; track %.2f m]",
                  e.sector.c_str(), e.walker_yields ? "yields" : "non-yielding", e.walker_speed_mps,
                  e.walker_closing_mps, lead(e.forward_lead_s, e.forward_plan).c_str(),
                  lead(e.any_lead_s, e.any_plan).c_str(), e.track_gap_m);
    out += line;
  }
  return out;
}

// Over every run: the close passes by what the navigator perceived of the walker.
std::string PerceptionSummary(const std::vector<RunResult>& results) {
  int n = 0, in_view = 0, moving = 0, standing = 0, never = 0, none = 0, unseen = 0;
  int near = 0, guard = 0;
  std::vector<double> error_m, velocity_error;
  for (const auto& r : results) {
    for (const auto& p : r.perceptions) {
      ++n;
      in_view += p.in_view ? 1 : 0;
      guard += p.action.find("guard") != std::string::npos ? 1 : 0;
      if (p.track < 0) {
        ++none;
        continue;
      }
      moving += p.track_moving ? 1 : 0;
      standing += !p.track_moving && p.track_walker ? 1 : 0;
      never += p.track_walker ? 0 : 1;
      unseen += p.track_age_s > 0.0 ? 1 : 0;
      near += p.track_gap_m < 0.6 ? 1 : 0;
      error_m.push_back(p.track_error_m);
      velocity_error.push_back(p.velocity_error_mps);
    }
  }
  char line[512];
  std::snprintf(line, sizeof(line),
                "close passes perceived: %d; walker in the camera's view %d, out of it %d; "
                "tracked %d (moving %d, walker standing %d, never moved %d; not seen in the "
                "last update %d; disc within 0.6 m of the footprint %d; centre off the true "
                "one mean %.2f max %.2f m; velocity error mean %.2f max %.2f m/s), no track %d; "
                "the crowd guard acting in %d\n",
                n, in_view, n - in_view, n - none, moving, standing, never, unseen, near,
                Mean(error_m), Max(error_m), Mean(velocity_error), Max(velocity_error), none,
                guard);
  return line;
}

// Over all runs: the close passes by the robot's state, the walker's side and kind, and the
// latest moment an escape existed.
std::string EscapeSummary(const std::vector<RunResult>& results) {
  int total = 0, standing = 0, non_yielding = 0;
  std::map<std::string, int> sectors;
  constexpr double kBins[] = {0.1, 0.2, 0.3, 0.5, 1.0, 1.5};
  int forward[7] = {0}, any[7] = {0};
  const auto bin = [&](double s) {
    if (s < 0.0) return 6;
    for (int b = 0; b < 6; ++b) {
      if (s <= kBins[b] + 1e-9) return b;
    }
    return 6;
  };
  for (const auto& r : results) {
    for (size_t i = 0; i < r.escapes.size(); ++i) {
      const auto& e = r.escapes[i];
      ++total;
      standing += r.close_passes[i].robot_standing ? 1 : 0;
      non_yielding += e.walker_yields ? 0 : 1;
      ++sectors[e.sector];
      ++forward[bin(e.forward_lead_s)];
      ++any[bin(e.any_lead_s)];
    }
  }
  const auto row = [&](const int* counts) {
    char t[200];
    std::snprintf(t, sizeof(t),
                  "0.1 s %d, 0.2 s %d, 0.3 s %d, 0.5 s %d, 1.0 s %d, 1.5 s %d, none %d", counts[0],
                  counts[1], counts[2], counts[3], counts[4], counts[5], counts[6]);
    return std::string(t);
  };
  char head[200];
  std::snprintf(head, sizeof(head),
                "close-pass escapes: %d passes (robot standing %d; walker non-yielding %d; ", total,
                standing, non_yielding);
  std::string out = head;
  out += "walker at the " + CauseList(sectors) +
         "); latest escape before the pass began, forward-only: " + row(forward) +
         "; reversing allowed: " + row(any) + "\n";
  return out;
}

// Route (blue), path driven (green, red while avoiding), walkers at a few instants (grey
// dots, darker later), goal; deviation over time below (shaded while avoiding).
void WritePlot(const std::string& path, const std::string& title,
               const std::vector<Eigen::Vector2d>& route, const std::vector<Eigen::Vector2d>& driven,
               const std::vector<bool>& avoiding, const std::vector<std::vector<Eigen::Vector2d>>& walkers,
               const std::vector<double>& deviation_m, double dt_s) {
  cv::Mat canvas(900, 900, CV_8UC3, cv::Scalar(255, 255, 255));
  double x0 = 1e9, x1 = -1e9, y0 = 1e9, y1 = -1e9;
  for (const auto& p : route) {
    x0 = std::min(x0, p.x()), x1 = std::max(x1, p.x()), y0 = std::min(y0, p.y()), y1 = std::max(y1, p.y());
  }
  for (const auto& p : driven) {
    x0 = std::min(x0, p.x()), x1 = std::max(x1, p.x()), y0 = std::min(y0, p.y()), y1 = std::max(y1, p.y());
  }
  x0 -= 1.5, x1 += 1.5, y0 -= 1.5, y1 += 1.5;
  // Equal scales on both axes.
  const double span = std::max(x1 - x0, (y1 - y0) * 800.0 / 480.0);
  const double cx = 0.5 * (x0 + x1), cy = 0.5 * (y0 + y1);
  const PlotAxes top(cv::Rect(80, 40, 800, 480), cx - 0.5 * span, cx + 0.5 * span,
                     cy - 0.5 * span * 480.0 / 800.0, cy + 0.5 * span * 480.0 / 800.0);
  top.DrawFrame(&canvas, "x (m, world)", "y (m)");
  for (size_t k = 0; k < walkers.size(); ++k) {
    const int shade = 220 - static_cast<int>(140.0 * k / std::max<size_t>(1, walkers.size() - 1));
    for (const auto& w : walkers[k]) {
      const cv::Point2d px = top.ToPixel(w.x(), w.y());
      if (top.area().contains(cv::Point(px))) cv::circle(canvas, px, 3, cv::Scalar(shade, shade, shade), -1, cv::LINE_AA);
    }
  }
  std::vector<cv::Point2d> route_px;
  for (const auto& p : route) route_px.push_back(top.ToPixel(p.x(), p.y()));
  DrawPolyline(&canvas, route_px, cv::Scalar(200, 80, 0), 3);
  for (size_t i = 1; i < driven.size(); ++i) {
    cv::line(canvas, top.ToPixel(driven[i - 1].x(), driven[i - 1].y()),
             top.ToPixel(driven[i].x(), driven[i].y()),
             avoiding[i] ? cv::Scalar(0, 0, 230) : cv::Scalar(0, 160, 0), 2, cv::LINE_AA);
  }
  if (!route.empty()) {
    cv::circle(canvas, top.ToPixel(route.back().x(), route.back().y()), 8, cv::Scalar(200, 80, 0), 2, cv::LINE_AA);
  }
  DrawText(&canvas, title, cv::Point(80, 28), 0.5, cv::Scalar(0, 0, 0));
  const double t_end = std::max(dt_s, deviation_m.size() * dt_s);
  const PlotAxes bottom(cv::Rect(80, 600, 800, 240), 0.0, t_end, 0.0,
                        std::max(0.1, 1.1 * Max(deviation_m)));
  for (size_t i = 0; i < deviation_m.size() && i < avoiding.size(); ++i) {
    if (!avoiding[i]) continue;
    const cv::Point2d a = bottom.ToPixel(i * dt_s, 0.0);
    const cv::Point2d b = bottom.ToPixel((i + 1) * dt_s, 0.0);
    cv::rectangle(canvas, cv::Point(a.x, bottom.area().y), cv::Point(b.x, bottom.area().br().y),
                  cv::Scalar(220, 220, 255), -1);
  }
  bottom.DrawFrame(&canvas, "time (s)  [shaded: avoiding]", "deviation (m)");
  std::vector<cv::Point2d> dev_px;
  for (size_t i = 0; i < deviation_m.size(); ++i) dev_px.push_back(bottom.ToPixel(i * dt_s, deviation_m[i]));
  DrawPolyline(&canvas, dev_px, cv::Scalar(0, 0, 0), 1);
  cv::imwrite(path, canvas);
}

int Run(const tools::CliArgs& args) {
  const std::string config = args.Get("config", "config/sim/nav_cafeteria.yaml");
  const std::string nav_config = args.Get("nav-config", "config/navigation.yaml");
  const std::string slam_config = args.Get("slam-config", "config");
  const int runs = args.GetInt("runs", 10);
  const double route_m = args.GetDouble("route-m", 12.0);
  const int first_seed = args.GetInt("first-crowd-seed", 101);
  const std::string out = args.Get("out", "out/nav");
  const double timeout_factor = args.GetDouble("timeout-factor", 3.0);
  const bool trace_fixes = args.Has("trace-fixes");
  const bool trace_deviation = args.Has("trace-deviation");
  const bool classify = args.Has("classify-close-passes");
  const bool scanner = args.Has("scanner");
  if (runs < 1 || route_m <= 0.5 || timeout_factor <= 1.0) {
    return tools::UsageError(kTool, "--runs >= 1, --route-m > 0.5 and --timeout-factor > 1");
  }
  std::filesystem::create_directories(out);
  cv::setNumThreads(1);  // single thread, as the other benchmarks measure

  sim::SimOptions sim_options = sim::LoadSimOptions(config);
  if (scanner) sim_options.scanner.enabled = true;
  NavigationOptions nav_options = LoadNavigationOptions(nav_config);
  nav_options.navigator.robot_radius_m = sim_options.drive.robot_radius_m;
  SlamOptions slam_options = LoadSlamOptions(slam_config);
  const double dt = 1.0 / sim_options.frame_rate_hz;

  // --- Teach run: map the route's first route_m + 1.5 m. ---
  sim::SimOptions teach_options = sim_options;
  teach_options.route.laps = 0.0;
  teach_options.num_frames = static_cast<int>(
      std::ceil(((route_m + 1.5) / teach_options.route.speed_mps + 3.0) * teach_options.frame_rate_hz));
  const sim::Simulator teach(teach_options);
  slam_options.frontend.fusion.base_to_camera = teach.T_base_camera();
  const Pose3 T_base_camera = teach.T_base_camera();
  const std::string map_path = out + "/teach_map.db";
  Pose3 world_from_map = Pose3::Identity();
  std::map<int64_t, Eigen::Vector2d> teach_base_at;  // stamp (ns) -> true base position
  std::map<int64_t, Pose3> teach_world_base;          // stamp (ns) -> true base pose
  // The goal: the taught place the teach run reached at route_m. goal_world is its true
  // position (the teach run's ground truth, for judging), goal_map where the teach map puts it
  // (given to the navigator).
  Eigen::Vector2d goal_world = Eigen::Vector2d::Zero(), goal_map = Eigen::Vector2d::Zero();
  double goal_yaw_world = 0.0, goal_yaw_map = 0.0;  // the base's heading there, likewise
  {
    SlamSystem mapping(slam_options, teach.intrinsics());
    ProgressBar bar(teach.size(), "teach");
    double along = 0.0;
    bool goal_set = false;
    Time goal_stamp;
    for (size_t i = 0; i < teach.size(); ++i) {
      mapping.AddWheelOdometry(teach.stamp(i), teach.odometry(i).T_odom_base);
      const sim::SimFrame f = teach.Render(i);
      mapping.ProcessFrame(f.stamp, f.bgr, f.depth_m);
      teach_base_at[teach.stamp(i).nanoseconds()] = teach.T_world_base(i).translation().head<2>();
      teach_world_base[teach.stamp(i).nanoseconds()] = teach.T_world_base(i);
      if (i > 0) {
        along += (teach.T_world_base(i).translation() - teach.T_world_base(i - 1).translation()).norm();
      }
      if (!goal_set && along >= route_m) {
        goal_world = teach.T_world_base(i).translation().head<2>();
        goal_yaw_world = ToPose2D(teach.T_world_base(i)).yaw_rad;
        goal_stamp = teach.stamp(i);
        goal_set = true;
      }
      bar.Update(i + 1);
    }
    bar.Finish();
    mapping.Flush();  // a keyframe held for its next frame (map_features.source: tracker)
    if (!goal_set) return tools::Failure(kTool, "teach run shorter than the route");
    const Status saved = mapping.Save(map_path);
    if (!saved.ok()) return tools::Failure(kTool, "saving the teach map: " + saved.reason());
    const Trajectory map_trajectory = mapping.MapTrajectory();
    world_from_map = teach.T_world_camera(0) * map_trajectory.front().pose.inverse();
    const auto at_goal = std::find_if(map_trajectory.begin(), map_trajectory.end(),
                                      [&](const StampedPose& p) { return p.stamp == goal_stamp; });
    if (at_goal == map_trajectory.end()) {
      return tools::Failure(kTool, "the teach map has no pose at the goal frame");
    }
    goal_map = (at_goal->pose * T_base_camera.inverse()).translation().head<2>();
    goal_yaw_map = ToPose2D(at_goal->pose * T_base_camera.inverse()).yaw_rad;
    const Eigen::Vector2d anchored =
        (world_from_map.inverse() * Eigen::Vector3d(goal_world.x(), goal_world.y(), 0.0)).head<2>();
    std::printf("teach: %zu frames, %d keyframes, %zu loop closures, goal (%.2f, %.2f) world\n",
                teach.size(), mapping.map().size(), mapping.loop_closures().size(),
                goal_world.x(), goal_world.y());
    std::printf("goal: the taught place after %.1f m, (%.2f, %.2f) in the map (the teach map's "
                "estimate; the true place through the map's start would be %.3f m away: the "
                "teach map's drift there); judged against (%.2f, %.2f) world, its true position\n",
                route_m, goal_map.x(), goal_map.y(), (anchored - goal_map).norm(), goal_world.x(),
                goal_world.y());
  }
  const Pose3 map_from_world = world_from_map.inverse();

  // --- Repeat runs in closed loop. ---
  std::vector<RunResult> results;
  const double nominal_s = route_m / nav_options.controller.max_speed_mps;
  const size_t max_frames = static_cast<size_t>(timeout_factor * nominal_s / dt);
  for (int k = 0; k < runs; ++k) {
    RunResult run;
    run.crowd_seed = first_seed + k;
    sim::SimOptions options = sim_options;
    options.crowd_seed = run.crowd_seed;
    sim::ClosedLoopSimulator sim(options);
    SlamSystem slam(slam_options, sim.intrinsics());
    if (!slam.Load(map_path, false).ok() || !slam.SetMode("localization").ok()) {
      return tools::Failure(kTool, "cannot load the teach map for localization");
    }
    // Each map keyframe's base: true (teach run) and in the map.
    std::vector<std::pair<Pose3, Pose3>> anchors;
    std::vector<int> anchor_ids;
    for (const auto& kf : slam.map().keyframes()) {
      const auto it = teach_world_base.find(kf.stamp.nanoseconds());
      if (it != teach_world_base.end()) {
        anchors.emplace_back(it->second, kf.global_pose * T_base_camera.inverse());
        anchor_ids.push_back(kf.id);
      }
    }
    // The true base placed in the map through the nearest keyframe (its map pose times the
    // true motion from where the teach run took it): what localization against the map should
    // give. *anchor gets that keyframe's index.
    const auto map_truth = [&anchors](const Pose3& world_base, size_t* anchor) {
      size_t a = 0;
      for (size_t j = 1; j < anchors.size(); ++j) {
        if ((anchors[j].first.translation() - world_base.translation()).squaredNorm() <
            (anchors[a].first.translation() - world_base.translation()).squaredNorm()) {
          a = j;
        }
      }
      if (anchor) *anchor = a;
      return Pose3(anchors[a].second * anchors[a].first.inverse() * world_base);
    };
    Navigator nav(nav_options);
    const Status map_ok = nav.SetMap(slam.map(), T_base_camera);
    if (!map_ok.ok()) return tools::Failure(kTool, map_ok.reason());

    std::vector<Eigen::Vector2d> driven, route_world;
    std::vector<bool> avoiding;
    std::vector<std::vector<Eigen::Vector2d>> walkers;
    std::vector<double> deviation;
    double last_avoid_s = -1e9;
    bool in_rejoin = false;
    size_t relocs = 0;
    NavigationStatus status;
    sim::ClosePassOptions close_options;
    close_options.clearance_m = kTargetClearanceM - kClearanceToleranceM;
    close_options.standing_mps = kStandingMps;
    sim::ClosePassLog close_passes(close_options);
    // --classify-close-passes: the simulator before each of the last steps, and the navigator's
    // nearest walker track then.
    constexpr size_t kMaxLeadSteps = 15;
    std::deque<sim::ClosedLoopSimulator> history;
    std::deque<double> track_gap_history;
    const sim::EscapeOptions escape_options;
    std::vector<double> walker_radii;
    for (size_t j = 0; j < sim.num_pedestrians(); ++j) {
      walker_radii.push_back(sim.pedestrian_radius_m(j));
    }
    ProgressBar bar(max_frames, "run " + std::to_string(k + 1) + "/" + std::to_string(runs));
    for (size_t i = 0; i < max_frames; ++i) {
      const auto t_render = std::chrono::steady_clock::now();
      const sim::SimFrame f = sim.Render();
      const std::optional<PlanarScan> scan =
          sim.options().scanner.enabled ? std::optional<PlanarScan>(sim.RenderScan()) : std::nullopt;
      const auto t0 = std::chrono::steady_clock::now();
      const double cpu0 = ThreadCpuMs();
      slam.AddWheelOdometry(f.stamp, f.odometry.T_odom_base);
      const Pose3 map_from_odom_before = slam.MapFromOdom();
      const SlamFrameResult r = slam.ProcessFrame(f.stamp, f.bgr, f.depth_m);
      // Where the base would be in the map without this frame's fix (odometry since the last).
      const Pose3 predicted_map_base =
          map_from_odom_before * r.frontend.odom_camera * T_base_camera.inverse();
      bool fix = false;
      if (i == 0) {  // the initial pose, as rviz's /initialpose gives it
        slam.SetInitialPose(map_from_world * f.T_world_camera, r.frontend.odom_camera);
        fix = true;
      } else if (slam.relocalizations() > relocs) {
        fix = true;
      }
      relocs = slam.relocalizations();
      const Pose3 T_map_base = slam.MapFromOdom() * r.frontend.odom_camera * T_base_camera.inverse();
      nav.UpdatePose(f.stamp, T_map_base, fix);
      if (scan) nav.UpdateScan(*scan, sim.T_base_scanner());
      nav.UpdateDepth(f.stamp, f.depth_m, sim.intrinsics(), T_base_camera);
      if (i == 0) {
        const Status goal = nav.SetGoal(goal_map, T_map_base, goal_yaw_map);
        if (!goal.ok()) std::fprintf(stderr, "run %d: %s\n", k + 1, goal.reason().c_str());
        // The route where it truly is: the teach run's true base positions at the route's
        // keyframes, then the goal.
        std::vector<Eigen::Vector2d> nodes;
        for (size_t n = 0; n < nav.route_keyframes().size(); ++n) {
          const int id = nav.route_keyframes()[n];
          const auto it = id >= 0 ? teach_base_at.find(slam.map().keyframe(id).stamp.nanoseconds())
                                  : teach_base_at.end();
          if (it != teach_base_at.end()) {
            nodes.push_back(it->second);
          } else if (n + 1 == nav.route_keyframes().size()) {
            nodes.push_back(goal_world);
          }
        }
        route_world = ResamplePolyline(nodes, 0.02);
      }
      status = nav.Update(f.stamp, dt);
      const auto t1 = std::chrono::steady_clock::now();
      run.frame_ms.push_back(ThreadCpuMs() - cpu0);
      run.frame_wall_ms.push_back(std::chrono::duration<double, std::milli>(t1 - t0).count());
      run.frame_with_render_ms.push_back(std::chrono::duration<double, std::milli>(t1 - t_render).count());

      const Eigen::Vector2d truth(sim.planar_pose().x_m, sim.planar_pose().y_m);
      const double dev = PointPolylineDistance(truth, route_world);
      const double loc_error =
          ((world_from_map * T_map_base).translation() - f.T_world_base.translation())
              .head<2>()
              .norm();
      run.localization_error_m.push_back(loc_error);
      double loc_error_map = 0.0;
      if (!anchors.empty()) {
        const Pose3 truth_map = map_truth(f.T_world_base, nullptr);
        loc_error_map = (truth_map.translation() - T_map_base.translation()).head<2>().norm();
        run.localization_error_map_m.push_back(loc_error_map);
      }
      if (r.keyframe && i > 0) {
        ++run.localization_keyframes;
        if (!fix) {
          // Counted by kind: numbers left out.
          std::string kind;
          for (char c : r.update.loop.status.reason()) {
            if ((c >= '0' && c <= '9') || c == '.') {
              if (kind.empty() || kind.back() != '#') kind += '#';
            } else {
              kind += c;
            }
          }
          ++run.no_fix_reasons[kind];
        }
      }
      if (fix && i > 0) {
        run.fix_jump_m.push_back(
            (T_map_base.translation() - predicted_map_base.translation()).head<2>().norm());
        size_t anchor = 0;
        const Pose3 truth_map =
            anchors.empty() ? T_map_base : map_truth(f.T_world_base, &anchor);
        const double before =
            (truth_map.translation() - predicted_map_base.translation()).head<2>().norm();
        run.error_before_fix_m.push_back(before);
        run.error_after_fix_m.push_back(loc_error_map);
        if (trace_fixes) {
          std::string used;
          for (const auto& e : r.update.loop.evidence) {
            if (!e.rejected.empty()) continue;
            char c[64];
            std::snprintf(c, sizeof(c), " %d%s(%d)", e.candidate_id, e.proximity ? "p" : "",
                          e.registration.inliers);
            used += c;
          }
          const int nearest_id = anchors.empty() ? -1 : anchor_ids[anchor];
          std::fprintf(stderr,
                       "seed %d t %.1f fix: correction %.3f m, error %.3f m (map: before %.3f, "
                       "after %.3f m); candidates (inliers):%s; nearest keyframe %d\n",
                       run.crowd_seed, i * dt, run.fix_jump_m.back(), loc_error, before,
                       loc_error_map, used.c_str(), nearest_id);
        }
      } else if (trace_fixes && r.keyframe && i > 0) {
        std::fprintf(stderr, "seed %d t %.1f no fix: %s; error (map) %.3f m\n", run.crowd_seed,
                     i * dt, r.update.loop.status.reason().c_str(), loc_error_map);
      }
      const double t_s = i * dt;
      if (status.avoiding) last_avoid_s = t_s;
      driven.push_back(truth);
      avoiding.push_back(status.avoiding);
      deviation.push_back(dev);
      // The final turn in place is counted apart: it changes neither position nor route.
      const bool turning = status.state == NavigationState::kTurningToGoal;
      if (turning && run.final_turn_s == 0.0) {  // the position reached: time and distance end
        run.time_s = t_s;
        run.distance_m = sim.distance_driven_m();
        run.end_pose = truth;
      }
      if (turning) run.final_turn_s += dt;
      if (!turning) run.deviation_m.push_back(dev);
      // Outside avoidance: not on a detour nor yielding, and back on the route since (the
      // navigator's rejoining flag: localized cross-track within rejoin_tolerance_m and heading
      // within rejoin_heading_rad of the route, at most rejoin_max_s after the last avoiding
      // frame); _3s: not avoiding for 3 s.
      if (!turning && !status.avoiding && !status.rejoining) {
        if (dev > Max(run.deviation_outside_m)) {
          char w[256];
          std::snprintf(w, sizeof(w),
                        "%.3f m at %.1f s (%.1f s after the last avoidance), %s, command %.2f "
                        "m/s %.2f rad/s, as localized %.3f m, localization error %.3f m",
                        dev, t_s, t_s - last_avoid_s, NavigationStateName(status.state),
                        status.command.linear_mps, status.command.angular_radps,
                        status.cross_track_m, loc_error_map);
          run.worst_outside = w;
        }
        run.deviation_outside_m.push_back(dev);
        run.localization_error_outside_m.push_back(loc_error_map);
        run.believed_deviation_outside_m.push_back(
            PointPolylineDistance(T_map_base.translation().head<2>(), nav.route()));
      } else if (!turning) {
        run.deviation_avoidance_m.push_back(dev);
      }
      if (!turning && t_s - last_avoid_s > 3.0) run.deviation_outside_3s_m.push_back(dev);
      if (trace_deviation) {
        std::fprintf(stderr,
                     "seed %d t %.1f dev %.4f localized %.4f error %.4f heading %.3f at (%.2f, "
                     "%.2f) %s%s%s cmd %.2f %.2f v %.2f%s\n",
                     run.crowd_seed, t_s, dev,
                     PointPolylineDistance(T_map_base.translation().head<2>(), nav.route()),
                     loc_error_map, status.heading_error_rad, truth.x(), truth.y(),
                     NavigationStateName(status.state), status.avoiding ? " avoiding" : "",
                     status.rejoining ? " rejoining" : "", status.command.linear_mps,
                     status.command.angular_radps, sim.true_velocity().linear_mps,
                     fix ? " fix" : "");
      }
      if (!turning && status.rejoining && !status.avoiding) {
        if (!in_rejoin) {
          in_rejoin = true;
          run.rejoin_s.push_back(0.0);
          run.rejoin_m.push_back(0.0);
          run.rejoin_deviation_m.push_back(0.0);
        } else {
          run.rejoin_s.back() += dt;
          run.rejoin_m.back() += (driven.back() - driven[driven.size() - 2]).norm();
        }
        run.rejoin_deviation_m.back() = std::max(run.rejoin_deviation_m.back(), dev);
      } else {
        in_rejoin = false;
      }
      run.avoid_frames += status.avoiding ? 1 : 0;
      run.stop_frames += status.state == NavigationState::kSafetyStop ? 1 : 0;
      run.plans += status.planned ? 1 : 0;
      run.yield_frames += status.yielding ? 1 : 0;
      run.gap_filter_frames += status.gap_filtered ? 1 : 0;
      run.blind_side_frames += status.blind_side_slowed ? 1 : 0;
      run.approach_frames += status.approach_slowed ? 1 : 0;
      run.evasive_frames += status.evaded ? 1 : 0;
      run.stopping_frames += status.stopping_braked ? 1 : 0;
      run.stale_fix_frames += status.stale_fix_slowed ? 1 : 0;
      run.relaxed_frames += status.path_checks_relaxed ? 1 : 0;
      run.time_cap_hits += status.planning_time_cap_hit ? 1 : 0;
      run.state_checks += status.planning_state_checks;
      if (std::abs(status.command.linear_mps) < kStandingMps && !turning &&
          status.state != NavigationState::kReached) {
        ++run.standing_frames[StandingCause(status)];
      }
      if (i % 50 == 0) {
        walkers.push_back(WalkerPositions(sim));
      }
      bar.Update(i + 1);
      if (status.state == NavigationState::kReached || status.state == NavigationState::kAborted) break;
      const int people_before = sim.pedestrian_collisions().collisions;
      const Eigen::Vector2d robot_before = truth;
      const std::vector<Eigen::Vector2d> walkers_before = WalkerPositions(sim);
      if (classify) {
        history.push_back(sim);
        if (history.size() > kMaxLeadSteps) history.pop_front();
      }
      const size_t passes_before = close_passes.passes().size();
      sim.Step(status.command, dt);
      const double walker_clearance = sim.PedestrianClearanceM();
      run.min_walker_clearance_m = std::min(run.min_walker_clearance_m, walker_clearance);
      {
        // What the navigator knew: the footprint's gap to the nearest walker track (moving or
        // moved once) and to the nearest obstacle cell, from its localized pose.
        double tracked_gap = std::numeric_limits<double>::infinity(), cell_gap = tracked_gap;
        if (nav.pose()) {
          const Eigen::Vector2d p = nav.pose()->position();
          for (const TrackedObstacle& t : nav.tracker().tracks()) {
            if (!t.moving && !t.was_moving) continue;
            tracked_gap =
                std::min(tracked_gap, (p - nav.tracker().Predict(t, 0.0)).norm() - t.radius_m -
                                          nav_options.navigator.robot_radius_m);
          }
          cell_gap = nav.obstacles().Clearance(p.x(), p.y()) - nav_options.navigator.robot_radius_m;
        }
        char context[240];
        std::snprintf(context, sizeof(context), "%s%s%s%s%s%s, walker track %.2f m, cell %.2f m",
                      NavigationStateName(status.state),
                      status.yielding ? (", guard: " + status.guard_action).c_str() : "",
                      status.gap_filtered ? ", gap filter" : "",
                      status.blind_side_slowed ? ", blind side" : "",
                      status.evaded ? ", evasive" : "",
                      status.stopping_braked ? ", stopping distance" : "", tracked_gap, cell_gap);
        close_passes.Step(sim.elapsed_s(), robot_before,
                          Eigen::Vector2d(sim.planar_pose().x_m, sim.planar_pose().y_m),
                          sim.true_velocity().linear_mps, sim.options().drive.robot_radius_m,
                          walkers_before, WalkerPositions(sim), walker_radii, context);
        if (classify) {
          track_gap_history.push_back(tracked_gap);
          if (track_gap_history.size() > kMaxLeadSteps) track_gap_history.pop_front();
        }
        if (close_passes.passes().size() > passes_before) {
          run.perceptions.push_back(PerceivePass(close_passes.passes().back().walker, sim,
                                                 walkers_before, nav, status, map_from_world,
                                                 nav_options.obstacle_grid.max_range_m, dt));
        }
        if (classify && close_passes.passes().size() > passes_before) {
          run.escapes.push_back(ClassifyClosePass(close_passes.passes().back(), sim, walkers_before,
                                                  history, track_gap_history, escape_options, dt));
        }
      }
      if (sim.pedestrian_collisions().collisions > people_before) {
        // Where the walker touched (bearing from the robot's heading) and what the robot did.
        const auto people = sim.pedestrians();
        const sim::PlanarPose& r = sim.planar_pose();
        size_t nearest = 0;
        for (size_t j = 1; j < people.size(); ++j) {
          if (std::hypot(people[j].x_m - r.x_m, people[j].y_m - r.y_m) <
              std::hypot(people[nearest].x_m - r.x_m, people[nearest].y_m - r.y_m)) {
            nearest = j;
          }
        }
        const double bearing = WrapAngleRad(
            std::atan2(people[nearest].y_m - r.y_m, people[nearest].x_m - r.x_m) - r.yaw_rad);
        char line[160];
        std::snprintf(line, sizeof(line), " [t %.1f s, bearing %.0f deg, v %.2f m/s, %s%s]",
                      sim.elapsed_s(), bearing * 180.0 / M_PI, sim.true_velocity().linear_mps,
                      NavigationStateName(status.state),
                      status.yielding ? (", guard: " + status.guard_action).c_str() : "");
        run.contacts += line;
      }
    }
    bar.Finish();
    const Eigen::Vector2d truth(sim.planar_pose().x_m, sim.planar_pose().y_m);
    if (run.final_turn_s > 0.0) run.turn_drift_m = (truth - run.end_pose).norm();
    run.end_pose = truth;
    run.goal_error_m = (truth - goal_world).norm();
    run.yaw_error_rad = WrapAngleRad(sim.planar_pose().yaw_rad - goal_yaw_world);
    run.reached = status.state == NavigationState::kReached &&
                  run.goal_error_m <= kSuccessToleranceM &&
                  (nav_options.navigator.goal_yaw_tolerance_rad <= 0.0 ||
                   std::abs(run.yaw_error_rad) <= kSuccessYawRad);
    run.end = std::string(NavigationStateName(status.state)) +
              (status.reason.empty() ? "" : " (" + status.reason + ")");
    if (status.state == NavigationState::kActive || status.state == NavigationState::kSafetyStop) {
      run.end += " timeout";
    }
    if (run.final_turn_s == 0.0) {
      run.time_s = sim.elapsed_s();
      run.distance_m = sim.distance_driven_m();
    }
    run.collisions = sim.collisions();
    run.static_collisions = sim.static_collisions().collisions;
    run.pedestrian_collisions = sim.pedestrian_collisions().collisions;
    run.min_clearance_m = sim.min_clearance_m();
    run.relocalizations = slam.relocalizations();
    run.close_passes = close_passes.passes();
    char title[256];
    std::snprintf(title, sizeof(title),
                  "run %d, crowd seed %d: %s, goal error %.3f m, mean dev %.3f m, max %.3f m",
                  k + 1, run.crowd_seed, run.reached ? "reached" : "NOT reached", run.goal_error_m,
                  Mean(run.deviation_m), Max(run.deviation_m));
    WritePlot(out + "/run_" + std::to_string(k + 1) + ".png", title, route_world, driven, avoiding,
              walkers, deviation, dt);
    std::printf(
        "run %d crowd seed %d: %s, %s, goal error %.3f m, %.1f s, %.2f m driven, %.3f m/s, "
        "deviation mean %.3f max %.3f m (outside avoidance mean %.3f max %.3f m), avoiding %d "
        "frames, %d plans (%ld state checks, %d stopped by the time cap), yielding %d frames, "
        "gap filter %d frames, blind side %d frames, approach speed %d frames, evasive %d frames, stopping distance %d "
        "frames, stale fix %d frames, relaxed checks %d frames, safety stops %d frames, "
        "collisions %d (static "
        "%d, walkers %d), min "
        "clearance %.3f m, "
        "walkers within %.1f m %d times (closest %.3f m), %zu relocalizations, end (%.6f, %.6f), "
        "frame p95 %.1f ms CPU (wall %.1f ms, with "
        "rendering %.1f ms)\n",
        k + 1, run.crowd_seed, run.reached ? "reached" : "not reached", run.end.c_str(),
        run.goal_error_m, run.time_s, run.distance_m, run.mean_speed(), Mean(run.deviation_m),
        Max(run.deviation_m), Mean(run.deviation_outside_m), Max(run.deviation_outside_m),
        run.avoid_frames, run.plans, run.state_checks, run.time_cap_hits, run.yield_frames,
        run.gap_filter_frames, run.blind_side_frames, run.approach_frames, run.evasive_frames, run.stopping_frames,
        run.stale_fix_frames, run.relaxed_frames, run.stop_frames, run.collisions, run.static_collisions, run.pedestrian_collisions,
        run.min_clearance_m, kTargetClearanceM, static_cast<int>(run.close_passes.size()),
        run.min_walker_clearance_m, run.relocalizations, run.end_pose.x(), run.end_pose.y(),
        Percentile(run.frame_ms, 0.95), Percentile(run.frame_wall_ms, 0.95),
        Percentile(run.frame_with_render_ms, 0.95));
    std::printf("  final turn at the goal: %.1f s, true heading %.1f deg from the teach run's, "
                "moved %.3f m in it\n",
                run.final_turn_s, run.yaw_error_rad * 180.0 / M_PI, run.turn_drift_m);
    const auto last = [](const std::vector<double>& v) { return v.empty() ? 0.0 : v.back(); };
    std::printf("  localization error: in the world (through the teach map's start) mean %.3f max "
                "%.3f m, at the end %.3f m; against the map (nearest keyframe) mean %.3f max %.3f "
                "m, at the end %.3f m; %zu fixes, correction mean %.3f max %.3f m\n",
                Mean(run.localization_error_m), Max(run.localization_error_m),
                last(run.localization_error_m), Mean(run.localization_error_map_m),
                Max(run.localization_error_map_m), last(run.localization_error_map_m),
                run.fix_jump_m.size(), Mean(run.fix_jump_m), Max(run.fix_jump_m));
    std::printf("  outside avoidance (%zu frames): deviation mean %.3f max %.3f m; as localized "
                "(the estimate's distance from the route in the map) mean %.3f max %.3f m; "
                "localization error against the map mean %.3f max %.3f m\n",
                run.deviation_outside_m.size(), Mean(run.deviation_outside_m),
                Max(run.deviation_outside_m), Mean(run.believed_deviation_outside_m),
                Max(run.believed_deviation_outside_m), Mean(run.localization_error_outside_m),
                Max(run.localization_error_outside_m));
    if (!run.worst_outside.empty()) {
      std::printf("  largest deviation outside avoidance: %s\n", run.worst_outside.c_str());
    }
    std::printf(
        "  rejoins: %zu, longest %.1f s, farthest %.2f m driven, largest deviation in one "
        "%.3f m\n",
        run.rejoin_s.size(), Max(run.rejoin_s), Max(run.rejoin_m), Max(run.rejoin_deviation_m));
    std::string reasons;
    for (const auto& [reason, count] : run.no_fix_reasons) {
      reasons += (reasons.empty() ? "" : "; ") + std::to_string(count) + "x " + reason;
    }
    std::printf("  fixes at %zu of %d keyframes; error against the map before a fix mean %.3f "
                "max %.3f m, after mean %.3f max %.3f m%s%s\n",
                run.error_after_fix_m.size(), run.localization_keyframes,
                Mean(run.error_before_fix_m), Max(run.error_before_fix_m),
                Mean(run.error_after_fix_m), Max(run.error_after_fix_m),
                reasons.empty() ? "" : "; no fix: ", reasons.c_str());
    std::printf("  standing frames by cause: %s\n", CauseList(run.standing_frames).c_str());
    if (!run.contacts.empty()) std::printf("  contacts:%s\n", run.contacts.c_str());
    if (!run.close_passes.empty()) {
      std::printf(
          "  close passes (closest; robot speed when it began; gap closed by the robot / "
          "the walker from 1 m and below 0.3 m; what the robot did):%s\n",
          ClosePassList(run.close_passes).c_str());
    }
    if (!run.perceptions.empty()) {
      std::printf(
          "  close passes perceived (walker's bearing, in the camera's view or not; the "
          "navigator's track nearest it: state, last seen, centre off the true one, disc gap to "
          "the footprint, speed vs true; the command):%s\n",
          PerceptionList(run.perceptions).c_str());
    }
    if (!run.escapes.empty()) {
      std::printf(
          "  close-pass escapes (walker: where, yields, speed, closing speed; latest "
          "escape before the pass began: forward-only, reversing allowed; the navigator's "
          "nearest walker track then):%s\n",
          EscapeList(run.escapes).c_str());
    }
    std::fflush(stdout);
    results.push_back(std::move(run));
  }

  int reached = 0, collisions = 0, static_collisions = 0, time_cap_hits = 0, close_passes = 0;
  int close_standing = 0, close_robot_closed = 0, close_robot_inside = 0;
  double min_walker_clearance = 1e9;
  std::vector<double> dev, dev_out, dev_out_3s, frame_ms, frame_wall_ms, frame_render_ms, speeds;
  std::vector<double> turn_s, yaw_error_deg;  // the final turns at the goal
  std::vector<double> loc_map, loc_out, believed_out, before_fix, after_fix, dev_in;
  std::vector<double> rejoin_s, rejoin_m;
  double min_clearance = 1e9;
  std::map<std::string, int> standing;
  for (const auto& r : results) {
    for (const auto& [cause, n] : r.standing_frames) standing[cause] += n;
    reached += r.reached ? 1 : 0;
    collisions += r.collisions;
    static_collisions += r.static_collisions;
    time_cap_hits += r.time_cap_hits;
    close_passes += static_cast<int>(r.close_passes.size());
    for (const auto& c : r.close_passes) {
      close_standing += c.robot_standing ? 1 : 0;
      close_robot_closed += c.robot_moving() && c.robot_closed_more() ? 1 : 0;
      close_robot_inside += c.robot_moving() && c.robot_inside_m > c.walker_inside_m ? 1 : 0;
    }
    min_walker_clearance = std::min(min_walker_clearance, r.min_walker_clearance_m);
    frame_wall_ms.insert(frame_wall_ms.end(), r.frame_wall_ms.begin(), r.frame_wall_ms.end());
    dev.insert(dev.end(), r.deviation_m.begin(), r.deviation_m.end());
    dev_out.insert(dev_out.end(), r.deviation_outside_m.begin(), r.deviation_outside_m.end());
    dev_out_3s.insert(dev_out_3s.end(), r.deviation_outside_3s_m.begin(),
                      r.deviation_outside_3s_m.end());
    frame_ms.insert(frame_ms.end(), r.frame_ms.begin(), r.frame_ms.end());
    frame_render_ms.insert(frame_render_ms.end(), r.frame_with_render_ms.begin(), r.frame_with_render_ms.end());
    speeds.push_back(r.mean_speed());
    turn_s.push_back(r.final_turn_s);
    yaw_error_deg.push_back(std::abs(r.yaw_error_rad) * 180.0 / M_PI);
    dev_in.insert(dev_in.end(), r.deviation_avoidance_m.begin(), r.deviation_avoidance_m.end());
    loc_map.insert(loc_map.end(), r.localization_error_map_m.begin(),
                   r.localization_error_map_m.end());
    loc_out.insert(loc_out.end(), r.localization_error_outside_m.begin(),
                   r.localization_error_outside_m.end());
    believed_out.insert(believed_out.end(), r.believed_deviation_outside_m.begin(),
                        r.believed_deviation_outside_m.end());
    before_fix.insert(before_fix.end(), r.error_before_fix_m.begin(), r.error_before_fix_m.end());
    after_fix.insert(after_fix.end(), r.error_after_fix_m.begin(), r.error_after_fix_m.end());
    min_clearance = std::min(min_clearance, r.min_clearance_m);
    rejoin_s.insert(rejoin_s.end(), r.rejoin_s.begin(), r.rejoin_s.end());
    rejoin_m.insert(rejoin_m.end(), r.rejoin_m.begin(), r.rejoin_m.end());
  }
  std::printf("outside avoidance: mean deviation %.3f m, max deviation %.3f m (%zu of %zu frames; "
              "3 s after avoiding: mean %.3f m, max %.3f m, %zu frames); collisions with walls/furniture %d, with walkers %d; min clearance %.3f m; "
              "walkers within %.1f m of the footprint %d times (closest %.3f m); frame p95 CPU %.1f ms, wall %.1f ms, wall with rendering %.1f ms; plans stopped by the "
              "time cap %d\n",
              Mean(dev_out), Max(dev_out), dev_out.size(), dev.size(), Mean(dev_out_3s),
              Max(dev_out_3s), dev_out_3s.size(), static_collisions,
              collisions - static_collisions, min_clearance, kTargetClearanceM, close_passes,
              min_walker_clearance, Percentile(frame_ms, 0.95),
              Percentile(frame_wall_ms, 0.95), Percentile(frame_render_ms, 0.95), time_cap_hits);
  // Avoidance manoeuvres (avoiding or rejoining) apart from the rest; outside avoidance the true
  // deviation beside the one the robot believes (its estimate to the route in the map) and the
  // localization error against the map: the true deviation differs from the believed one by
  // at most the localization error.
  std::printf("deviation in avoidance manoeuvres (avoiding or rejoining): mean %.3f max %.3f m "
              "(%zu frames); outside avoidance: true mean %.3f max %.3f m, as localized mean "
              "%.3f max %.3f m, localization error against the map mean %.3f max %.3f m (all "
              "frames: mean %.3f max %.3f m); at the fixes: before mean %.3f max %.3f m, after "
              "mean %.3f max %.3f m (%zu fixes)\n",
              Mean(dev_in), Max(dev_in), dev_in.size(), Mean(dev_out), Max(dev_out),
              Mean(believed_out), Max(believed_out), Mean(loc_out), Max(loc_out), Mean(loc_map),
              Max(loc_map), Mean(before_fix), Max(before_fix), Mean(after_fix), Max(after_fix),
              after_fix.size());
  // How long the rejoins (counted as part of the manoeuvre) last: the label is honest only if
  // they are short.
  std::printf(
      "rejoins after avoidance: %zu, duration mean %.2f s, p95 %.2f s, max %.2f s; "
      "distance driven mean %.2f m, max %.2f m\n",
      rejoin_s.size(), Mean(rejoin_s), Percentile(rejoin_s, 0.95), Max(rejoin_s), Mean(rejoin_m),
      Max(rejoin_m));
  std::printf("final turn at the goal (navigator.goal_yaw_tolerance_rad %.3f): mean %.1f s, max "
              "%.1f s; true heading error at the end mean %.1f max %.1f deg\n",
              nav_options.navigator.goal_yaw_tolerance_rad, Mean(turn_s), Max(turn_s),
              Mean(yaw_error_deg), Max(yaw_error_deg));
  std::printf("standing frames by cause (commanded |v| < %.2f m/s): %s\n", kStandingMps,
              CauseList(standing).c_str());
  std::printf("goal: the taught place (teach run after %.1f m) given in map coordinates; reached: "
              "stopped with the true centre within %.2f m of its true teach position (navigator "
              "stops within %.2f m of the goal in the map)\n",
              route_m, kSuccessToleranceM, nav_options.navigator.goal_tolerance_m);
  // The strict clearance beside the contacts: every episode with a walker closer than 0.3 m to
  // the footprint, by cause.
  std::printf(
      "clearance %.1f m: collisions %d (walls/furniture %d, walkers %d); walkers closer "
      "than %.1f m to the footprint %d times, closest %.3f m: robot moving %d (its own "
      "motion closed more of the gap below %.1f m in %d, of the gap from 1 m in %d), "
      "robot standing (walked into) %d\n",
      kTargetClearanceM, collisions, static_collisions, collisions - static_collisions,
      kTargetClearanceM, close_passes, min_walker_clearance, close_passes - close_standing,
      kTargetClearanceM, close_robot_inside, close_robot_closed, close_standing);
  if (classify) std::printf("%s", EscapeSummary(results).c_str());
  std::printf("%s", PerceptionSummary(results).c_str());
  std::printf("navigation: %d/%d goals reached, mean deviation %.3f m, max deviation %.3f m, "
              "collisions %d, mean speed %.3f m/s, frame p95 %.1f ms\n",
              reached, runs, Mean(dev), Max(dev), collisions, Mean(speeds),
              Percentile(frame_ms, 0.95));
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  try {
    const tools::CliArgs args(argc, argv,
                              {"config", "nav-config", "slam-config", "runs", "route-m",
                               "first-crowd-seed", "out", "timeout-factor"},
                              {"trace-fixes", "trace-deviation", "classify-close-passes", "scanner"});
    if (args.help()) return tools::PrintUsage(kTool);
    if (!args.positional().empty()) return tools::UsageError(kTool, "unexpected argument " + args.positional()[0]);
    return Run(args);
  } catch (const std::invalid_argument& e) {
    return tools::UsageError(kTool, e.what());
  } catch (const std::exception& e) {
    return tools::Failure(kTool, e.what());
  }
}
