// The navigation loop (thesis 6.1.2 with local obstacle avoidance), ROS-free: the global route
// is Dijkstra's shortest path over the learned map's keyframe graph (GraphPlanner), taken in
// base_link positions (the map's keyframe poses are camera poses: each is moved to the base with
// the base -> camera extrinsic). The robot follows it with the eq. 6.5 pointer: p marks the route
// node the robot is at, the local target is node p + omega (at least lookahead_m ahead), and at
// every localization fix (relocalization or loop closure) p is re-anchored to the node nearest
// the localized pose, as LoopFollower re-anchors at its matched model i. While the route ahead
// is free the tracked path is the route itself; when an obstacle (a person) blocks it (for
// detour_delay_s, default 0), OMPL plans a detour in a window around the route (a few Hz) to
// the first free route point ahead.
// A pure-pursuit controller turns the path into velocity commands, with a safety stop.
// Walkers: the obstacle cells seen in each depth image are tracked (ObstacleTracker: clusters ->
// tracks with velocities) and the CrowdGuard checks every command against their predicted
// motion, slowing, stopping, backing off or swerving when a walker would come too close.
//
// Use per frame (any order of the three inputs; times are the sensor stamps):
//   navigator.SetMap(map, T_base_camera);           // once per learned map
//   navigator.SetGoal(goal_xy_in_map, T_map_base, goal_yaw);  // route from the robot to the goal
//   (at the goal's position it turns in place to goal_yaw: navigator.goal_yaw_tolerance_rad)
//   each frame: UpdatePose(stamp, T_map_base, fix); UpdateDepth(stamp, depth, K, T_base_camera);
//               NavigationStatus s = Update(now, dt);  -> s.command to the base
// The map frame is the learned map's (SlamSystem in localization mode, alpha = 1); T_map_base
// is its localized camera pose times T_base_camera^-1.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>
#include <opencv2/core.hpp>

#include "core/common/camera.h"
#include "core/common/pose.h"
#include "core/common/status.h"
#include "core/common/time.h"
#include "core/common/velocity_command.h"
#include "core/map/hybrid_map.h"
#include "core/nav/graph_planner.h"
#include "core/nav/local_planner.h"
#include "core/nav/navigation_options.h"
#include "core/nav/obstacle_grid.h"
#include "core/nav/planar_pose.h"
#include "core/nav/tracking_controller.h"

namespace icgm {

enum class NavigationState {
  kIdle,        // no goal
  kActive,      // following the route (possibly around an obstacle)
  kSafetyStop,  // stopped: an obstacle is within the stop distance ahead (resumes by itself)
  kReached,     // within goal_tolerance_m of the goal (occupied: see NavigatorOptions); then zero
                // (and within goal_yaw_tolerance_rad of the goal's yaw when it has one)
  // At the goal's position, turning in place to its yaw (no translation).
  kTurningToGoal,
  kAborted,     // given up, `reason` says why; zero command from then on
};
const char* NavigationStateName(NavigationState state);

struct NavigationStatus {
  NavigationState state = NavigationState::kIdle;
  std::string reason;          // why aborted / stopped; empty otherwise
  VelocityCommand command;     // zero unless kActive
  double cross_track_m = 0.0;  // distance from the localized base to the global route
  // The localized heading relative to the route's direction where the robot projects onto it.
  double heading_error_rad = 0.0;
  double distance_to_goal_m = 0.0;  // straight line, from the localized base
  // The goal's yaw minus the localized heading (wrapped); 0 when the goal's orientation is
  // ignored (no yaw, or navigator.goal_yaw_tolerance_rad 0).
  double goal_yaw_error_rad = 0.0;
  double since_fix_m = 0.0;         // driven (as localized) since the last localization fix
  // navigator.stale_fix_distance_m capped the top speed in this update.
  bool stale_fix_slowed = false;
  int pointer = 0;                  // eq. 6.5 pointer p (index into route_nodes())
  // The route ahead is blocked: the tracked path is an OMPL detour, or the robot waits for one.
  bool avoiding = false;
  // Not avoiding any more, but not yet back within rejoin_tolerance_m of the route (and, with
  // navigator.rejoin_heading_rad, heading along it) since the last avoidance: the end of the
  // manoeuvre.
  bool rejoining = false;
  // The crowd guard replaced the controller's command (`guard_action` says how): a walker's
  // predicted motion would have come within the guard's gap. Counted as avoidance.
  bool yielding = false;
  std::string guard_action;
  // The crowd guard's gap filter (crowd_guard.gap_filter_m) slowed the command: held, the
  // footprint would have come closer to a walker than the filter's gap. Not counted as avoidance.
  bool gap_filtered = false;
  // The blind-side speed (crowd_guard.blind_side_speed_mps) capped the command: a walker out
  // of the camera's view is near the footprint. Not counted as avoidance.
  bool blind_side_slowed = false;
  // The approach speed near tracks (crowd_guard.approach_gap_m) slowed the command.
  bool approach_slowed = false;
  // The evasive rule (crowd_guard.evasive_gap_m) replaced the command: it would have brought
  // the footprint closer to a walker than the rule allows. Not counted as avoidance.
  bool evaded = false;
  // The stopping-distance rule (crowd_guard.stopping_gap_m) slowed the command: from it the
  // robot could not have stopped short of a walker. Not counted as avoidance.
  bool stopping_braked = false;
  // navigator.path_checks_relax_after_s: the path checks are relaxed to the bare footprint in
  // this update (the robot stood blocked).
  bool path_checks_relaxed = false;
  double predicted_gap_m = 0.0;        // footprint to the nearest moving walker over the horizon
  bool planned = false;                // OMPL ran in this update
  double planning_ms = 0.0;            // wall time of that planning
  int planning_state_checks = 0;       // its work (deterministic)
  bool planning_time_cap_hit = false;  // the wall-clock safety stop ended it
};

// navigator.stale_fix_distance_m: the top speed allowed after driving since_fix_m since the
// last localization fix (infinity: no cap; options off or not yet that far): top_speed_mps up to
// the distance, then falling linearly to stale_fix_speed_mps at twice the distance, then held.
double StaleFixSpeedCap(double since_fix_m, double top_speed_mps, const NavigatorOptions& options);

class Navigator {
 public:
  explicit Navigator(NavigationOptions options = NavigationOptions());

  // The learned map's graph in base_link positions (keyframe camera pose * T_base_camera^-1).
  // Fails on an empty map. Clears the goal.
  Status SetMap(const HybridMap& map, const Pose3& T_base_camera);
  // Dijkstra route from the node nearest the robot (T_map_base) to the node nearest the goal,
  // ending at the goal itself; goal_yaw_rad (map frame): the heading to end with
  // (navigator.goal_yaw_tolerance_rad; none: the orientation is ignored). Fails with a reason (and
  // the state becomes kAborted) when the goal is off the map (farther than max_goal_off_map_m from
  // every node), inside a known obstacle, or unreachable on the graph.
  Status SetGoal(const Eigen::Vector2d& goal_m, const Pose3& T_map_base,
                 std::optional<double> goal_yaw_rad = std::nullopt);
  // A route given directly (map frame, start .. goal) instead of the map graph (e.g. a path
  // planned elsewhere); every point is a route node. Fails on fewer than 2 points.
  Status SetRoute(const std::vector<Eigen::Vector2d>& route_m,
                  std::optional<double> goal_yaw_rad = std::nullopt);
  void Cancel();  // back to kIdle, zero command

  // The localized pose of base_link in the map. `fix` = this pose comes from a localization fix
  // (relocalization / loop closure / initial pose): the pointer is re-anchored, and the
  // distance driven since the last fix (navigator.stale_fix_distance_m) starts again.
  void UpdatePose(Time stamp, const Pose3& T_map_base, bool fix);
  // A depth image for the obstacle grid, placed with the latest pose. Fails before any pose.
  Status UpdateDepth(Time stamp, const cv::Mat& depth_m, const CameraIntrinsics& intrinsics,
                     const Pose3& T_base_camera);
  // A planar range scan (e.g. a laser scanner seeing beside and behind the robot), mounted at
  // T_base_scanner. It is kept until the next depth image (UpdateDepth) within 0.2 s of its
  // stamp, which adds it to the obstacle grid after the depth, as part of the same frame: the
  // walker tracker sees the cells of both. Each scan is used once.
  void UpdateScan(const PlanarScan& scan, const Pose3& T_base_scanner);
  // One control cycle at `now` lasting dt_s: checks the abort rules, moves the pointer, plans
  // when needed and returns the command with the state. Never throws.
  NavigationStatus Update(Time now, double dt_s);

  const NavigationStatus& status() const { return status_; }
  const ObstacleGrid& obstacles() const { return grid_; }
  const ObstacleTracker& tracker() const { return tracker_; }
  const std::optional<Pose2D>& pose() const { return pose_; }  // localized base, map frame
  ObstacleGrid* mutable_obstacles() { return &grid_; }
  // The global route (map frame): its nodes (keyframes, then the goal) and its dense polyline.
  const std::vector<Eigen::Vector2d>& route_nodes() const { return route_nodes_; }
  // The map keyframe id of each route node (-1: not a keyframe, e.g. the goal or SetRoute's).
  const std::vector<int>& route_keyframes() const { return route_keyframes_; }
  const std::vector<Eigen::Vector2d>& route() const { return route_; }
  // The path the controller tracks now (the route ahead, or a detour followed by the route).
  const std::vector<Eigen::Vector2d>& local_path() const { return local_path_; }
  // Distance from a point to the global route polyline (m); 0 without a route.
  double CrossTrack(const Eigen::Vector2d& p) const;
  const NavigationOptions& options() const { return options_; }

 private:
  NavigationStatus Abort(const std::string& reason);
  void StartRoute(std::vector<Eigen::Vector2d> nodes, std::vector<int> keyframes);
  void ReanchorPointer(const Eigen::Vector2d& p);
  void AdvancePointer(const Eigen::Vector2d& p);
  // Index into route_ of the point nearest p within [from, to).
  size_t NearestRouteIndex(const Eigen::Vector2d& p, size_t from, size_t to) const;
  // Builds local_path_ from the route (free) or a detour (blocked); false when blocked and no
  // detour was found (reason set).
  bool RefreshLocalPath(Time now, NavigationStatus* status);
  // The merge curve (navigator.merge_distance_m) from the robot's pose onto the route, followed
  // by the rest of the route; false (path untouched) when the heading is too far off, the route
  // left is too short or the curve is not free.
  // The route's unit direction at route_ index i (over a few samples either side).
  Eigen::Vector2d RouteTangent(size_t i) const;
  bool MergePath(std::vector<Eigen::Vector2d>* path) const;
  // navigator.rejoin_dubins_radius_m: the arc that settles the robot's present turn rate, then
  // the Dubins curve onto a route point ahead that stays nearest the route and is free, then the
  // rest of the route; false (path untouched) when the heading is too far off, the route left is
  // too short or no curve is free.
  bool DubinsRejoinPath(std::vector<Eigen::Vector2d>* path) const;
  // LocalPlanner::SegmentFree on the path grid, the escape measured from the robot when
  // navigator.path_checks_inflated is on (`route`: the route check ahead; else a detour or a
  // rejoin curve, navigator.path_checks_inflated_route_only).
  bool PathSegmentFree(const Eigen::Vector2d& a, const Eigen::Vector2d& b,
                       bool route = false) const;
  // navigator.path_checks_relax_after_s: relaxes the path checks once the robot has stood
  // blocked that long, for path_checks_relax_for_s.
  void UpdatePathChecksRelaxed(Time now);
  // The footprint is free from `from` to points[0] and on along the first `count` points
  // (at least the first); false for no points.
  bool PolylineFree(const Eigen::Vector2d& from, const std::vector<Eigen::Vector2d>& points,
                    size_t count) const;
  // navigator.detour_join_m: replaces the end of `path` (a detour whose point `junction` is
  // route_[goal_index], followed by the route) by a curve joining the route tangentially; sets
  // *join_end to the route_ index where the curve ends. False (path untouched) when there is no
  // room (the junction at the goal), the detour meets the route too steeply or the curve is not
  // free.
  bool JoinDetour(std::vector<Eigen::Vector2d>* path, size_t junction, size_t goal_index,
                  size_t* join_end) const;
  // The route's direction at its end (over its last half metre), and whether p is abreast of
  // the goal or past it along that direction (navigator.goal_extension_m).
  Eigen::Vector2d GoalDirection() const;
  bool AbreastOfGoal(const Eigen::Vector2d& p) const;
  // The reach rule (goal_tolerance_m, and navigator.goal_line_tolerance_m when on).
  bool GoalReached(const NavigationStatus& status, double route_left_m) const;
  // The crowd guard's check of status->command; replaces it (and tells the controller) when a
  // walker's predicted motion comes too close.
  void GuardCommand(NavigationStatus* status);
  // The goal is occupied (navigator.goal_occupied_tolerance_m on): the free point nearest the
  // goal within the tolerance (ties: nearest the robot), or none.
  std::optional<Eigen::Vector2d> FreeNearGoal(const ObstacleGrid& grid) const;
  // Back on the route by the rejoin rule: the cross-track within rejoin_tolerance_m and (when
  // on) the heading within rejoin_heading_rad of the route's direction.
  bool OnRoute(const NavigationStatus& status) const;
  // The approach speed cap (navigator.approach_overshoot_m) at the status's heading error.
  double ApproachSpeed(const NavigationStatus& status) const;
  // navigator.forget_walker_trail: after the tracker's update at `stamp` with these fresh cells,
  // the memory cells of walkers seen now elsewhere are cleared from the grid.
  void ForgetWalkerTrails(Time stamp, const std::vector<Eigen::Vector2d>& fresh_cells);
  // navigator.walker_cells_ahead_only: the grid the path checks and the planner use (walker
  // cells beside and behind the robot dropped); the grid itself when off or nothing is dropped.
  void UpdatePathGrid();
  const ObstacleGrid& PathGrid() const { return path_grid_ ? *path_grid_ : CheckGrid(); }
  // navigator.walker_bodies_in_grid: the grid with the walkers' body discs (updated with every
  // depth image), else the grid itself.
  void UpdateBodyGrid();
  const ObstacleGrid& DriveGrid() const { return body_grid_ ? *body_grid_ : grid_; }
  // The grid the path checks start from: DriveGrid(), or the grid itself when the bodies are
  // for the drive only (navigator.walker_bodies_path_checks false).
  const ObstacleGrid& CheckGrid() const {
    return options_.navigator.walker_bodies_path_checks ? DriveGrid() : grid_;
  }
  // At the goal's position (navigator.goal_yaw_tolerance_rad): one step of the turn in place to
  // the goal's yaw, or reached once within the tolerance; aborts after no_progress_timeout_s.
  NavigationStatus TurnToGoal(Time now, double dt_s, NavigationStatus status);
  // Sets status->rejoining and stores the status.
  const NavigationStatus& Finish(Time now, const NavigationStatus& status);

  NavigationOptions options_;
  GraphPlanner graph_;
  bool has_map_ = false;
  ObstacleGrid grid_;
  LocalPlanner planner_;
  TrackingController controller_;
  ObstacleTracker tracker_;
  std::optional<ObstacleGrid> path_grid_;  // UpdatePathGrid's
  std::optional<ObstacleGrid> body_grid_;  // UpdateBodyGrid's
  // navigator.forget_walker_trail: grid cells marked by a walker (cell centre, track id).
  std::vector<std::pair<Eigen::Vector2d, int>> walker_cells_;
  CrowdGuard guard_;
  VelocityCommand sent_;  // the last command given to the base

  std::vector<Eigen::Vector2d> route_nodes_;
  std::vector<int> route_keyframes_;
  std::vector<size_t> node_route_index_;  // each node's index in route_
  std::vector<Eigen::Vector2d> route_;
  std::vector<Eigen::Vector2d> local_path_;
  size_t progress_index_ = 0;  // route_ index of the robot's projection
  int pointer_ = 0;

  std::optional<Pose2D> pose_;
  Time pose_stamp_, depth_stamp_, start_stamp_;
  bool have_depth_ = false;
  std::optional<PlanarScan> pending_scan_;  // UpdateScan's, until the next depth image
  Pose3 T_base_scanner_ = Pose3::Identity();
  bool pending_fix_ = false;
  double since_fix_m_ = 0.0;  // driven (as localized) since the last fix
  bool avoiding_ = false;
  bool rejoining_ = false;  // since the last avoidance, not yet back on the route
  Time last_avoiding_;      // the last frame that was avoiding (navigator.rejoin_max_s)
  // local_path_ is a detour whose end joins the route tangentially (navigator.detour_join_m),
  // ending at route_ index join_end_: once the route is free the robot still follows it there.
  bool joined_detour_ = false;
  size_t join_end_ = 0;
  // The tracked path is the route itself (free), or a rejoin curve onto it: no detour
  // (controller.lateral_rate_per_s may steer).
  bool route_tracked_ = false;
  bool avoided_ = false;  // an avoidance since the route started
  bool started_ = false;
  std::optional<Time> last_plan_;
  std::optional<Time> goal_blocked_since_;
  std::optional<double> goal_yaw_rad_;  // the goal's heading, when it is driven to
  // At the goal's position, turning to its yaw since.
  std::optional<Time> turning_since_;
  double goal_occupied_standing_s_ = 0.0;  // stood while the goal was occupied
  std::optional<Time> route_blocked_since_;
  // navigator.no_progress_timeout_s: the least route left so far and when it last shrank by
  // no_progress_m.
  double least_route_left_m_ = 0.0;
  std::optional<Time> progress_since_;
  std::optional<Time> stalled_since_;  // blocked without a detour since (continuously)
  std::optional<Time> relaxed_since_;  // the path checks relaxed since
  bool path_checks_relaxed_ = false;
  NavigationStatus status_;
};

}  // namespace icgm
