#include "core/nav/navigator.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>

#include "core/common/fixed_text.h"
#include "core/nav/dubins_rejoin.h"

namespace icgm {
namespace {

// Commanded slower than this, the robot stands (waiting on an occupied goal).
constexpr double kStandingMps = 0.05;
// navigator.goal_line_tolerance_m: the robot brakes to stop this far past the goal (along the
// route's last direction), so that it stops abreast of it.
constexpr double kGoalOvershootM = 0.03;
// navigator.detour_join_m: a detour meeting the route steeper than this is not rejoined by the
// curve (the robot turns on the route's carrot instead).
constexpr double kMaxJoinRad = 1.0;
// ... and the robot follows that curve after the route is free again only this close to it,
// and while the path ahead comes no farther than this beyond its own distance from the route.
constexpr double kJoinOffCurveM = 0.25;
constexpr double kJoinSlackM = 0.05;
// navigator.rejoin_dubins_radius_m: the join points tried (along the route from the robot's
// projection), the turn-rate settling arc's time step, and the weight of a curve's length
// against its largest distance from the route (m per m: 1 cm nearer is worth 0.5 m longer).
constexpr double kDubinsMinJoinM = 0.3;
constexpr double kDubinsMaxJoinM = 2.0;
constexpr double kDubinsJoinStepM = 0.1;
constexpr double kSettleStepS = 0.05;
constexpr double kDubinsLengthWeight = 0.02;
// UpdateScan: a scan joins the depth image of the same frame when their stamps are this close.
constexpr double kScanFrameWindowS = 0.2;

double PointSegmentDistance(const Eigen::Vector2d& p, const Eigen::Vector2d& a,
                            const Eigen::Vector2d& b) {
  const Eigen::Vector2d ab = b - a;
  const double len2 = ab.squaredNorm();
  const double s = len2 > 0.0 ? std::clamp((p - a).dot(ab) / len2, 0.0, 1.0) : 0.0;
  return (a + s * ab - p).norm();
}

// Offset from the route, along its normal, of a curve that joins it tangentially: the cubic
// Hermite with d(0) = offset, d'(0) = slope, d(1) = d'(1) = 0 at t = s / length in [0, 1].
double JoinOffset(double offset, double slope, double length, double t) {
  const double h00 = 2.0 * t * t * t - 3.0 * t * t + 1.0;
  const double h10 = t * t * t - 2.0 * t * t + t;
  return offset * h00 + length * slope * h10;
}

}  // namespace

const char* NavigationStateName(NavigationState state) {
  switch (state) {
    case NavigationState::kIdle:
      return "idle";
    case NavigationState::kActive:
      return "active";
    case NavigationState::kSafetyStop:
      return "safety_stop";
    case NavigationState::kReached:
      return "reached";
    case NavigationState::kTurningToGoal:
      return "turning_to_goal";
    case NavigationState::kAborted:
      return "aborted";
  }
  return "unknown";
}

Navigator::Navigator(NavigationOptions options)
    : options_([&] {
        options.obstacle_grid.robot_radius_m = options.navigator.robot_radius_m;
        options.controller.robot_radius_m = options.navigator.robot_radius_m;
        return options;
      }()),
      grid_(options_.obstacle_grid),
      planner_(options_.local_planner),
      controller_(options_.controller),
      tracker_(options_.tracker),
      guard_(options_.guard) {}

Status Navigator::SetMap(const HybridMap& map, const Pose3& T_base_camera) {
  if (map.keyframes().empty()) return Status::Error("navigation: the map has no keyframes");
  graph_ = GraphPlanner();
  const Pose3 T_camera_base = T_base_camera.inverse();
  for (const auto& kf : map.keyframes()) {
    Eigen::Vector3d p = (kf.global_pose * T_camera_base).translation();
    p.z() = 0.0;
    graph_.AddNode(p);
  }
  for (const auto& link : map.links()) {
    const Status s = graph_.AddEdge(link.from_id, link.to_id);
    if (!s.ok()) return Status::Error("navigation: map link: " + s.reason());
  }
  has_map_ = true;
  Cancel();
  return Status::Ok();
}

Status Navigator::SetGoal(const Eigen::Vector2d& goal_m, const Pose3& T_map_base,
                          std::optional<double> goal_yaw_rad) {
  if (!has_map_) {
    Abort("no map to plan on");
    return Status::Error(status_.reason);
  }
  if (goal_yaw_rad && !std::isfinite(*goal_yaw_rad)) {
    Abort("goal yaw " + FormatFixed(*goal_yaw_rad, 2) + " is not finite");
    return Status::Error(status_.reason);
  }
  if (!goal_m.allFinite()) {
    Abort("goal (" + FormatFixed(goal_m.x(), 2) + ", " + FormatFixed(goal_m.y(), 2) +
          ") is not a finite position");
    return Status::Error(status_.reason);
  }
  const Eigen::Vector3d goal3(goal_m.x(), goal_m.y(), 0.0);
  const int goal_node = graph_.NearestNode(goal3);
  const double off_map = (graph_.position(goal_node) - goal3).norm();
  if (off_map > options_.navigator.max_goal_off_map_m) {
    Abort("goal (" + FormatFixed(goal_m.x(), 2) + ", " + FormatFixed(goal_m.y(), 2) +
          ") is off the map: " + FormatFixed(off_map, 2) + " m from the nearest keyframe > " +
          FormatFixed(options_.navigator.max_goal_off_map_m, 2));
    return Status::Error(status_.reason);
  }
  if (grid_.Clearance(goal_m.x(), goal_m.y()) < options_.navigator.robot_radius_m) {
    Abort("goal (" + FormatFixed(goal_m.x(), 2) + ", " + FormatFixed(goal_m.y(), 2) +
          ") is inside an obstacle");
    return Status::Error(status_.reason);
  }
  Eigen::Vector3d robot = T_map_base.translation();
  robot.z() = 0.0;
  Route route;
  const Status planned = graph_.PlanRoute(graph_.NearestNode(robot), goal_node, &route);
  if (!planned.ok()) {
    Abort(planned.reason());
    return planned;
  }
  std::vector<Eigen::Vector2d> nodes;
  std::vector<int> keyframes = route.nodes;
  for (int n : route.nodes) nodes.push_back(graph_.position(n).head<2>());
  if ((nodes.back() - goal_m).norm() > 1e-3) {
    nodes.push_back(goal_m);
    keyframes.push_back(-1);
  }
  if (nodes.size() < 2) {
    nodes.insert(nodes.begin(), robot.head<2>());
    keyframes.insert(keyframes.begin(), -1);
  }
  StartRoute(std::move(nodes), std::move(keyframes));
  goal_yaw_rad_ = goal_yaw_rad;
  return Status::Ok();
}

Status Navigator::SetRoute(const std::vector<Eigen::Vector2d>& route_m,
                           std::optional<double> goal_yaw_rad) {
  if (route_m.size() < 2) return Status::Error("navigation: a route needs at least 2 points");
  if (goal_yaw_rad && !std::isfinite(*goal_yaw_rad)) {
    return Status::Error("navigation: the goal yaw is not finite");
  }
  StartRoute(route_m, std::vector<int>(route_m.size(), -1));
  goal_yaw_rad_ = goal_yaw_rad;
  return Status::Ok();
}

void Navigator::Cancel() {
  route_nodes_.clear();
  route_keyframes_.clear();
  route_.clear();
  node_route_index_.clear();
  local_path_.clear();
  controller_.Reset();
  sent_ = VelocityCommand();
  status_ = NavigationStatus();
}

NavigationStatus Navigator::Abort(const std::string& reason) {
  status_.state = NavigationState::kAborted;
  status_.reason = reason;
  status_.command = VelocityCommand();
  status_.avoiding = false;
  controller_.Reset();
  sent_ = VelocityCommand();
  return status_;
}

void Navigator::StartRoute(std::vector<Eigen::Vector2d> nodes, std::vector<int> keyframes) {
  route_nodes_ = std::move(nodes);
  route_keyframes_ = std::move(keyframes);
  route_.clear();
  node_route_index_.clear();
  for (size_t i = 0; i < route_nodes_.size(); ++i) {
    if (i == 0) {
      route_.push_back(route_nodes_[0]);
    } else {
      const auto seg = ResamplePolyline({route_nodes_[i - 1], route_nodes_[i]},
                                        options_.navigator.route_spacing_m);
      route_.insert(route_.end(), seg.begin() + 1, seg.end());
    }
    node_route_index_.push_back(route_.size() - 1);
  }
  local_path_.clear();
  progress_index_ = 0;
  pointer_ = 0;
  avoiding_ = false;
  rejoining_ = false;
  avoided_ = false;
  joined_detour_ = false;
  started_ = false;
  pending_fix_ = true;
  last_plan_.reset();
  goal_blocked_since_.reset();
  goal_yaw_rad_.reset();
  turning_since_.reset();
  goal_occupied_standing_s_ = 0.0;
  route_blocked_since_.reset();
  progress_since_.reset();
  stalled_since_.reset();
  relaxed_since_.reset();
  path_checks_relaxed_ = false;
  controller_.Reset();
  status_ = NavigationStatus();
  status_.state = NavigationState::kActive;
}

void Navigator::UpdatePose(Time stamp, const Pose3& T_map_base, bool fix) {
  const Pose2D pose = ToPose2D(T_map_base);
  since_fix_m_ = fix || !pose_ ? 0.0 : since_fix_m_ + (pose.position() - pose_->position()).norm();
  pose_ = pose;
  pose_stamp_ = stamp;
  if (fix) pending_fix_ = true;
}

Status Navigator::UpdateDepth(Time stamp, const cv::Mat& depth_m,
                              const CameraIntrinsics& intrinsics, const Pose3& T_base_camera) {
  if (!pose_) return Status::Error("navigation: depth before the first localized pose");
  const Status s = grid_.AddDepth(stamp, depth_m, intrinsics, T_base_camera, ToPose3(*pose_));
  if (s.ok()) {
    std::vector<Eigen::Vector2d> scan_cells;  // navigator.scan_tracker_only
    if (pending_scan_ &&
        std::abs(DurationSeconds(pending_scan_->stamp, stamp)) <= kScanFrameWindowS) {
      if (options_.navigator.scan_tracker_only) {
        scan_cells = grid_.ScanCells(*pending_scan_, T_base_scanner_, ToPose3(*pose_));
      } else {
        grid_.AddScan(*pending_scan_, T_base_scanner_, ToPose3(*pose_), true);
      }
    }
    pending_scan_.reset();
    depth_stamp_ = stamp;
    have_depth_ = true;
    std::vector<Eigen::Vector2d> cells = grid_.fresh_obstacles_m();
    for (const Eigen::Vector2d& c : scan_cells) {
      if (std::find(cells.begin(), cells.end(), c) == cells.end()) cells.push_back(c);
    }
    // The camera on the floor: the walkers' bodies lie behind what it sees of them.
    const Pose3 T_map_camera = ToPose3(*pose_) * T_base_camera;
    const Eigen::Vector3d camera = T_map_camera.translation();
    const Eigen::Vector3d axis = T_map_camera.rotation().col(2);
    CameraView view;
    view.viewpoint_m = Eigen::Vector2d(camera.x(), camera.y());
    view.yaw_rad = std::atan2(axis.y(), axis.x());
    view.half_fov_rad = std::atan2(0.5 * intrinsics.width_px, intrinsics.fx_px);
    view.range_m = grid_.options().max_range_m;
    tracker_.Update(stamp, cells, view.viewpoint_m, view);
    if (options_.navigator.forget_walker_trail) ForgetWalkerTrails(stamp, cells);
    UpdateBodyGrid();
  }
  return s;
}

void Navigator::UpdateBodyGrid() {
  body_grid_.reset();
  if (!options_.navigator.walker_bodies_in_grid) return;
  std::vector<Disc> bodies;
  for (const TrackedObstacle& t : tracker_.tracks()) {
    if (ObstacleTracker::IsWalker(t)) bodies.push_back(tracker_.BodyDisc(t, 0.0));
  }
  if (!bodies.empty()) body_grid_ = grid_.WithDiscs(bodies);
}

void Navigator::ForgetWalkerTrails(Time stamp, const std::vector<Eigen::Vector2d>& fresh_cells) {
  // Every track seen now claims the fresh cells within its radius plus the margin (also before
  // it counts as a walker); a claimed cell that is not seen again while its track, now a
  // walker, is seen elsewhere is the walker's trail.
  const double margin = options_.navigator.walker_cell_margin_m;
  const auto contains = [](const auto& v, const auto& x) {
    return std::find(v.begin(), v.end(), x) != v.end();
  };
  std::vector<const TrackedObstacle*> seen;
  std::vector<int> alive, walkers_seen;
  for (const TrackedObstacle& t : tracker_.tracks()) {
    alive.push_back(t.id);
    if (t.last_seen != stamp) continue;
    seen.push_back(&t);
    if (ObstacleTracker::IsWalker(t)) walkers_seen.push_back(t.id);
  }
  std::vector<Eigen::Vector2d> forget;
  std::vector<std::pair<Eigen::Vector2d, int>> kept;
  for (const auto& [cell, id] : walker_cells_) {
    if (contains(fresh_cells, cell)) continue;  // seen again now: claimed below
    if (contains(walkers_seen, id)) {
      forget.push_back(cell);
    } else if (contains(alive, id)) {
      kept.push_back({cell, id});  // out of view or not a walker (yet): the grid's memory
    }
  }
  grid_.Forget(forget);
  for (const Eigen::Vector2d& c : fresh_cells) {
    for (const TrackedObstacle* t : seen) {
      if ((c - t->position_m).norm() <= t->radius_m + margin) {
        kept.push_back({c, t->id});
        break;
      }
    }
  }
  walker_cells_ = std::move(kept);
}

void Navigator::UpdatePathGrid() {
  path_grid_.reset();
  if (!options_.navigator.walker_cells_ahead_only || !pose_) return;
  const NavigatorOptions& o = options_.navigator;
  const Eigen::Vector2d p = pose_->position();
  const Eigen::Vector2d heading(std::cos(pose_->yaw_rad), std::sin(pose_->yaw_rad));
  std::vector<Eigen::Vector2d> drop;
  for (const Eigen::Vector2d& c : CheckGrid().ObstacleCells(Disc{p, o.walker_cells_near_m})) {
    if ((c - p).dot(heading) >= o.robot_radius_m) continue;  // ahead of the footprint's front
    for (const TrackedObstacle& t : tracker_.tracks()) {
      if (ObstacleTracker::IsWalker(t) &&
          (c - t.position_m).norm() <= t.radius_m + o.walker_cell_margin_m) {
        drop.push_back(c);
        break;
      }
    }
  }
  if (!drop.empty()) path_grid_ = CheckGrid().Without(drop);
}

void Navigator::UpdateScan(const PlanarScan& scan, const Pose3& T_base_scanner) {
  pending_scan_ = scan;
  T_base_scanner_ = T_base_scanner;
}

size_t Navigator::NearestRouteIndex(const Eigen::Vector2d& p, size_t from, size_t to) const {
  size_t best = from;
  double best_d = std::numeric_limits<double>::infinity();
  for (size_t i = from; i < std::min(to, route_.size()); ++i) {
    const double d = (route_[i] - p).squaredNorm();
    if (d < best_d) {
      best_d = d;
      best = i;
    }
  }
  return best;
}

void Navigator::ReanchorPointer(const Eigen::Vector2d& p) {
  // LoopFollower's re-anchoring: the fix tells where on the route the robot is (near the
  // pointer: a route passing the same place twice is not confused).
  const size_t window =
      static_cast<size_t>(options_.navigator.pointer_search_m / options_.navigator.route_spacing_m);
  const size_t from = progress_index_ > window ? progress_index_ - window : 0;
  progress_index_ = NearestRouteIndex(p, from, progress_index_ + window + 1);
}

void Navigator::AdvancePointer(const Eigen::Vector2d& p) {
  // Between fixes the projection only moves forward.
  const size_t window =
      static_cast<size_t>(options_.navigator.pointer_search_m / options_.navigator.route_spacing_m);
  const size_t nearest = NearestRouteIndex(p, progress_index_, progress_index_ + window + 1);
  if ((route_[nearest] - p).squaredNorm() <= (route_[progress_index_] - p).squaredNorm()) {
    progress_index_ = nearest;
  }
}

double Navigator::CrossTrack(const Eigen::Vector2d& p) const {
  if (route_.empty()) return 0.0;
  double best = (route_[0] - p).norm();
  for (size_t i = 1; i < route_.size(); ++i) {
    best = std::min(best, PointSegmentDistance(p, route_[i - 1], route_[i]));
  }
  return best;
}

bool Navigator::RefreshLocalPath(Time now, NavigationStatus* status) {
  route_tracked_ = false;
  const Eigen::Vector2d p = pose_->position();
  const double spacing = options_.navigator.route_spacing_m;
  const size_t last = route_.size() - 1;
  const auto ahead = [&](double metres) {
    return std::min(last, progress_index_ + static_cast<size_t>(metres / spacing));
  };
  // The omega-step target: node p + omega, at least lookahead_m ahead.
  const int target_node =
      std::min<int>(pointer_ + options_.navigator.omega, static_cast<int>(route_nodes_.size()) - 1);
  const size_t target =
      std::max(node_route_index_[target_node], ahead(options_.navigator.lookahead_m));

  // Is the route itself free: from the robot to the route's carrot, then along the route?
  const size_t check_end = ahead(options_.navigator.rejoin_check_m);
  const size_t join = ahead(options_.controller.lookahead_min_m);
  UpdatePathGrid();
  bool route_free = PathSegmentFree(p, route_[join], true);
  for (size_t i = join; route_free && i < check_end; ++i) {
    route_free = PathSegmentFree(route_[i], route_[i + 1], true);
  }
  if (!route_free && !avoiding_) {
    if (!route_blocked_since_) route_blocked_since_ = now;
    // Keep to the route for a while: the blockage is often a walker passing by.
    route_free = DurationSeconds(now, *route_blocked_since_) < options_.navigator.detour_delay_s;
  } else if (route_free) {
    route_blocked_since_.reset();
  }
  if (route_free && joined_detour_ && progress_index_ < join_end_ && !local_path_.empty()) {
    // The route is free again, but the robot is on a detour whose end joins the route
    // tangentially: it follows that end while it stays free (rejoining), instead of turning
    // onto the route's carrot at an angle. Not when the path ahead goes farther from the route
    // than the robot is (the route is free: a detour may go a long way round), nor when the
    // robot is off the path.
    size_t closest = 0;
    double best = std::numeric_limits<double>::infinity();
    for (size_t i = 0; i < local_path_.size(); ++i) {
      const double d = (local_path_[i] - p).squaredNorm();
      if (d < best) best = d, closest = i;
    }
    bool follow = std::sqrt(best) <= kJoinOffCurveM;
    const double robot_off = CrossTrack(p) + kJoinSlackM;
    for (size_t i = closest; follow && i < local_path_.size(); ++i) {
      if (local_path_.size() - i <= route_.size() - 1 - join_end_) break;  // on the route
      follow = CrossTrack(local_path_[i]) <= robot_off;
    }
    std::vector<Eigen::Vector2d> rest(local_path_.begin() + static_cast<long>(closest),
                                      local_path_.end());
    const size_t check =
        std::min(rest.size(), static_cast<size_t>(options_.navigator.rejoin_check_m / spacing));
    const bool free = PolylineFree(p, rest, check);
    if (free && follow) {
      avoiding_ = false;
      local_path_ = std::move(rest);
      return true;
    }
  }
  if (route_free) {
    avoiding_ = false;
    joined_detour_ = false;
    route_tracked_ = true;
    local_path_.assign(route_.begin() + static_cast<long>(progress_index_), route_.end());
    if (options_.navigator.merge_distance_m > 0.0 &&
        (rejoining_ || CrossTrack(p) > options_.navigator.rejoin_tolerance_m)) {
      std::vector<Eigen::Vector2d> merge;
      if (MergePath(&merge)) local_path_ = std::move(merge);
    } else if (options_.navigator.rejoin_dubins_radius_m > 0.0 &&
               (rejoining_ || CrossTrack(p) > options_.navigator.rejoin_tolerance_m)) {
      std::vector<Eigen::Vector2d> rejoin;
      if (DubinsRejoinPath(&rejoin)) local_path_ = std::move(rejoin);
    }
    return true;
  }

  // Blocked: keep a detour that is still free unless it is time to plan again.
  bool detour_free = avoiding_ && !local_path_.empty();
  if (detour_free) {
    size_t closest = 0;
    double best = std::numeric_limits<double>::infinity();
    for (size_t i = 0; i < local_path_.size(); ++i) {
      const double d = (local_path_[i] - p).squaredNorm();
      if (d < best) best = d, closest = i;
    }
    local_path_.erase(local_path_.begin(), local_path_.begin() + static_cast<long>(closest));
    const size_t check = std::min(local_path_.size(),
                                  static_cast<size_t>(options_.navigator.rejoin_check_m / spacing));
    detour_free = PolylineFree(p, local_path_, check);
  }
  const bool due =
      !last_plan_ || DurationSeconds(now, *last_plan_) >= options_.navigator.replan_period_s;
  if (detour_free && !due) return true;
  if (!detour_free && !due && last_plan_ && !avoiding_) {
    // Planning failed a moment ago: wait for the next slot.
    status->reason = "blocked: waiting to plan again";
    return false;
  }

  // Planned on the grid with the walkers' swept area (when on and someone moves), else or
  // when that finds nothing, on the grid alone.
  std::vector<const ObstacleGrid*> grids;
  ObstacleGrid swept;
  if (options_.navigator.walker_sweep_s > 0.0) {
    const std::vector<Disc> discs = tracker_.SweptDiscs(options_.navigator.walker_sweep_s,
                                                        options_.navigator.walker_sweep_step_s);
    if (!discs.empty()) {
      swept = PathGrid().WithDiscs(discs);
      grids.push_back(&swept);
    }
  }
  grids.push_back(&PathGrid());
  LocalPath detour;
  bool ends_near_goal = false;
  Status planned = Status::Error("local planner: not run");
  size_t goal_index = target;
  // navigator.path_checks_relax_plan_clearance_m: a smaller clearance while stalled.
  const double plan_clearance =
      path_checks_relaxed_ ? options_.navigator.path_checks_relax_plan_clearance_m : -1.0;
  const auto t0 = std::chrono::steady_clock::now();
  for (const ObstacleGrid* g : grids) {
    // The first free route point at or beyond the target.
    goal_index = target;
    while (goal_index < last &&
           g->Clearance(route_[goal_index].x(), route_[goal_index].y()) < g->inflation_m()) {
      ++goal_index;
    }
    const Eigen::Vector2d dir =
        route_[std::min(last, goal_index + 1)] - route_[goal_index > 0 ? goal_index - 1 : 0];
    Pose2D goal{route_[goal_index].x(), route_[goal_index].y(), std::atan2(dir.y(), dir.x())};
    // The goal itself is occupied: the nearest free point within the tolerance instead; the
    // detour ends there.
    std::optional<Eigen::Vector2d> near_goal;
    if (goal_index == last && g->Occupied(route_[last].x(), route_[last].y())) {
      near_goal = FreeNearGoal(*g);
      if (near_goal) goal.x_m = near_goal->x(), goal.y_m = near_goal->y();
    }
    LocalPlanStats plan_stats;
    planned = planner_.Plan(*pose_, goal, *g, &detour, &plan_stats, plan_clearance);
    status->planning_state_checks += plan_stats.state_checks;
    status->planning_time_cap_hit = status->planning_time_cap_hit || plan_stats.time_cap_hit;
    ends_near_goal = near_goal.has_value();
    if (planned.ok()) break;
  }
  status->planned = true;
  status->planning_ms =
      std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
  last_plan_ = now;
  if (planned.ok()) {
    avoiding_ = true;
    joined_detour_ = false;
    local_path_ = detour.points_m;
    if (!ends_near_goal) {
      local_path_.insert(local_path_.end(), route_.begin() + static_cast<long>(goal_index) + 1,
                         route_.end());
      if (options_.navigator.detour_join_m > 0.0 && !detour.points_m.empty()) {
        joined_detour_ =
            JoinDetour(&local_path_, detour.points_m.size() - 1, goal_index, &join_end_);
      }
    }
    return true;
  }
  if (detour_free) return true;  // keep the previous detour
  avoiding_ = false;
  joined_detour_ = false;
  local_path_.clear();
  status->reason = "blocked: " + planned.reason();
  return false;
}

Eigen::Vector2d Navigator::RouteTangent(size_t i) const {
  // Over a few samples either side: smooth at the polyline's vertices.
  constexpr size_t kHalfWindow = 3;
  const size_t last = route_.size() - 1;
  const Eigen::Vector2d d =
      route_[std::min(last, i + kHalfWindow)] - route_[i > kHalfWindow ? i - kHalfWindow : 0];
  return d.normalized();
}

bool Navigator::MergePath(std::vector<Eigen::Vector2d>* path) const {
  const double spacing = options_.navigator.route_spacing_m;
  const size_t last = route_.size() - 1;
  const size_t k = progress_index_;
  if (k + 2 > last) return false;
  const auto tangent = [&](size_t i) { return RouteTangent(i); };
  const Eigen::Vector2d t0 = tangent(k);
  const Eigen::Vector2d n0(-t0.y(), t0.x());
  const double offset = (pose_->position() - route_[k]).dot(n0);  // signed, left positive
  const double heading_error = WrapAngleRad(pose_->yaw_rad - std::atan2(t0.y(), t0.x()));
  if (std::abs(heading_error) > options_.controller.turn_in_place_rad) return false;
  // Heading away from the route (after a swerve): a curve leaving along that heading would
  // swing farther out before it turns back; the route's carrot turns the robot back first.
  constexpr double kAlongRad = 0.05;
  if (offset * heading_error > 0.0 && std::abs(heading_error) > kAlongRad) return false;
  const size_t steps = std::min(
      last - k, static_cast<size_t>(std::lround(options_.navigator.merge_distance_m / spacing)));
  if (steps < 2) return false;
  const double length = steps * spacing;
  const double slope = std::tan(heading_error);
  std::vector<Eigen::Vector2d> merged;
  merged.reserve(last - k + 1);
  for (size_t i = 0; i <= steps; ++i) {
    const double t = static_cast<double>(i) / static_cast<double>(steps);
    const double d = JoinOffset(offset, slope, length, t);
    const Eigen::Vector2d ti = tangent(k + i);
    merged.push_back(route_[k + i] + d * Eigen::Vector2d(-ti.y(), ti.x()));
    if (i > 0 && !PathSegmentFree(merged[i - 1], merged[i])) return false;
  }
  merged.insert(merged.end(), route_.begin() + static_cast<long>(k + steps) + 1, route_.end());
  *path = std::move(merged);
  return true;
}

bool Navigator::DubinsRejoinPath(std::vector<Eigen::Vector2d>* path) const {
  const double spacing = options_.navigator.route_spacing_m;
  const size_t last = route_.size() - 1;
  const size_t k = progress_index_;
  if (k + 2 > last) return false;
  const Eigen::Vector2d t0 = RouteTangent(k);
  const double heading_error = WrapAngleRad(pose_->yaw_rad - std::atan2(t0.y(), t0.x()));
  if (std::abs(heading_error) > options_.controller.turn_in_place_rad) return false;
  // Where the robot gets while its present turn rate falls to zero: the curve starts there.
  std::vector<Eigen::Vector2d> settle;
  const Pose2D start =
      TurnSettlingArc(*pose_, sent_.linear_mps, sent_.angular_radps,
                      options_.controller.max_angular_acceleration_radps2, kSettleStepS, &settle);
  // The route near the curve, for its distance from the route.
  const size_t back = static_cast<size_t>(std::ceil(1.0 / spacing));
  const size_t route_from = k > back ? k - back : 0;
  const auto route_distance = [&](const Eigen::Vector2d& q, size_t to) {
    double best = std::numeric_limits<double>::infinity();
    for (size_t i = route_from + 1; i <= to; ++i) {
      best = std::min(best, PointSegmentDistance(q, route_[i - 1], route_[i]));
    }
    return best;
  };
  struct Candidate {
    size_t join = 0;
    double cost = 0.0;
    std::vector<Eigen::Vector2d> points;
  };
  std::vector<Candidate> candidates;
  for (double d = kDubinsMinJoinM; d <= kDubinsMaxJoinM + 1e-9; d += kDubinsJoinStepM) {
    const size_t j = std::min(last, k + static_cast<size_t>(std::lround(d / spacing)));
    if (!candidates.empty() && candidates.back().join == j) break;  // the route's end
    const Eigen::Vector2d tj = RouteTangent(j);
    const Pose2D end{route_[j].x(), route_[j].y(), std::atan2(tj.y(), tj.x())};
    double length = 0.0;
    Candidate c;
    c.join = j;
    c.points = DubinsCurve(start, end, options_.navigator.rejoin_dubins_radius_m, spacing, &length);
    const size_t to = std::min(last, j + back);
    double farthest = 0.0;
    for (const Eigen::Vector2d& q : settle) farthest = std::max(farthest, route_distance(q, to));
    for (const Eigen::Vector2d& q : c.points) farthest = std::max(farthest, route_distance(q, to));
    c.cost = farthest + kDubinsLengthWeight * length;
    candidates.push_back(std::move(c));
  }
  std::sort(candidates.begin(), candidates.end(),
            [](const Candidate& a, const Candidate& b) { return a.cost < b.cost; });
  const Eigen::Vector2d p = pose_->position();
  for (Candidate& c : candidates) {
    std::vector<Eigen::Vector2d> curve = settle;
    curve.insert(curve.end(), c.points.begin(), c.points.end());
    if (!PolylineFree(p, curve, curve.size())) continue;
    curve.insert(curve.end(), route_.begin() + static_cast<long>(c.join) + 1, route_.end());
    *path = std::move(curve);
    return true;
  }
  return false;
}

bool Navigator::PolylineFree(const Eigen::Vector2d& from,
                             const std::vector<Eigen::Vector2d>& points, size_t count) const {
  if (points.empty() || !PathSegmentFree(from, points.front())) return false;
  for (size_t i = 1; i < std::min(count, points.size()); ++i) {
    if (!PathSegmentFree(points[i - 1], points[i])) return false;
  }
  return true;
}

void Navigator::UpdatePathChecksRelaxed(Time now) {
  const NavigatorOptions& o = options_.navigator;
  if (o.path_checks_relax_after_s <= 0.0) return;
  if (stalled_since_ && DurationSeconds(now, *stalled_since_) >= o.path_checks_relax_after_s) {
    relaxed_since_ = now;
    stalled_since_.reset();
  }
  path_checks_relaxed_ =
      relaxed_since_ && DurationSeconds(now, *relaxed_since_) < o.path_checks_relax_for_s;
}

bool Navigator::PathSegmentFree(const Eigen::Vector2d& a, const Eigen::Vector2d& b,
                                bool route) const {
  const NavigatorOptions& o = options_.navigator;
  if (!o.path_checks_inflated || (!route && o.path_checks_inflated_route_only) || !pose_ ||
      path_checks_relaxed_) {
    return planner_.SegmentFree(a, b, PathGrid());
  }
  return planner_.SegmentFree(a, b, PathGrid(), pose_->position(), o.path_check_clearance_m);
}

bool Navigator::JoinDetour(std::vector<Eigen::Vector2d>* path, size_t junction, size_t goal_index,
                           size_t* join_end) const {
  const double spacing = options_.navigator.route_spacing_m;
  const double length_m = options_.navigator.detour_join_m;
  const size_t last = route_.size() - 1;
  if (junction < 2 || junction >= path->size()) return false;
  // Leave the detour a third of the curve's length before the junction (along the route): a
  // cubic from a straight approach at that distance reaches the route without crossing it.
  const Eigen::Vector2d tj = RouteTangent(goal_index);
  size_t a = junction;
  while (a > 1 && (route_[goal_index] - (*path)[a]).dot(tj) < length_m / 3.0) --a;
  if (a == junction) return false;
  const Eigen::Vector2d start = (*path)[a];
  const size_t back = static_cast<size_t>(std::ceil(2.0 * length_m / spacing));
  const size_t k =
      NearestRouteIndex(start, goal_index > back ? goal_index - back : 0, goal_index + 1);
  const Eigen::Vector2d tk = RouteTangent(k);
  const Eigen::Vector2d nk(-tk.y(), tk.x());
  const double offset = (start - route_[k]).dot(nk);  // signed, left positive
  const Eigen::Vector2d u = ((*path)[a + 1] - (*path)[a - 1]).normalized();
  const double psi = std::atan2(tk.x() * u.y() - tk.y() * u.x(), tk.dot(u));
  if (std::abs(psi) > kMaxJoinRad) return false;
  const size_t steps = std::min(last - k, static_cast<size_t>(std::lround(length_m / spacing)));
  // The curve ends beyond the junction, or at the goal when the detour joins there.
  if (steps < 2 || (k + steps <= goal_index && k + steps < last)) return false;
  const double length = steps * spacing;
  const double slope = std::tan(psi);
  std::vector<Eigen::Vector2d> joined(path->begin(), path->begin() + static_cast<long>(a));
  for (size_t i = 0; i <= steps; ++i) {
    const double t = static_cast<double>(i) / static_cast<double>(steps);
    const double d = JoinOffset(offset, slope, length, t);
    const Eigen::Vector2d ti = RouteTangent(k + i);
    const Eigen::Vector2d q = route_[k + i] + d * Eigen::Vector2d(-ti.y(), ti.x());
    // The planner's own rule: clear of the grid's inflation.
    if (PathGrid().Clearance(q.x(), q.y()) < PathGrid().inflation_m()) return false;
    joined.push_back(q);
  }
  joined.insert(joined.end(), route_.begin() + static_cast<long>(k + steps) + 1, route_.end());
  *path = std::move(joined);
  *join_end = k + steps;
  return true;
}

Eigen::Vector2d Navigator::GoalDirection() const {
  const size_t last = route_.size() - 1;
  const size_t back =
      std::min(last, static_cast<size_t>(std::lround(0.5 / options_.navigator.route_spacing_m)));
  const Eigen::Vector2d d = route_[last] - route_[last - back];
  return d.norm() > 1e-9 ? Eigen::Vector2d(d.normalized()) : Eigen::Vector2d(1.0, 0.0);
}

bool Navigator::AbreastOfGoal(const Eigen::Vector2d& p) const {
  return (p - route_.back()).dot(GoalDirection()) >= 0.0;
}

bool Navigator::GoalReached(const NavigationStatus& status, double route_left_m) const {
  const NavigatorOptions& o = options_.navigator;
  if (status.distance_to_goal_m > o.goal_tolerance_m || route_left_m > o.goal_tolerance_m + 0.5) {
    return false;
  }
  // Abreast of the goal but off the line is not enough (measured: a steep arrival stopped 8 cm
  // off it); the goal point lies on the line, so heading for it ends within the tolerance.
  return o.goal_line_tolerance_m <= 0.0 || status.cross_track_m <= o.goal_line_tolerance_m;
}

NavigationStatus Navigator::Update(Time now, double dt_s) {
  if (status_.state == NavigationState::kIdle || status_.state == NavigationState::kReached ||
      status_.state == NavigationState::kAborted) {
    status_.command = VelocityCommand();
    status_.planned = false;
    return status_;
  }
  if (!started_) {
    start_stamp_ = now;
    started_ = true;
  }
  const NavigatorOptions& o = options_.navigator;
  const double pose_age = DurationSeconds(now, pose_ ? pose_stamp_ : start_stamp_);
  if (pose_age > o.max_localization_age_s) {
    return Abort("no localization for " + FormatFixed(pose_age, 1) + " s > " +
                 FormatFixed(o.max_localization_age_s, 1));
  }
  const double depth_age = DurationSeconds(now, have_depth_ ? depth_stamp_ : start_stamp_);
  if (depth_age > o.max_depth_age_s) {
    return Abort("no depth for " + FormatFixed(depth_age, 1) + " s > " +
                 FormatFixed(o.max_depth_age_s, 1));
  }
  NavigationStatus status;
  status.state = NavigationState::kActive;
  if (!pose_) {
    status.reason = "waiting for localization";
    status_ = status;
    return status_;
  }
  const Eigen::Vector2d p = pose_->position();
  if (pending_fix_) {
    ReanchorPointer(p);
    pending_fix_ = false;
  } else {
    AdvancePointer(p);
  }
  // Pointer p: the last route node at or behind the robot's projection.
  pointer_ = 0;
  while (pointer_ + 1 < static_cast<int>(node_route_index_.size()) &&
         node_route_index_[pointer_ + 1] <= progress_index_) {
    ++pointer_;
  }
  status.pointer = pointer_;
  status.cross_track_m = CrossTrack(p);
  if (route_.size() > 1) {
    const Eigen::Vector2d t = RouteTangent(progress_index_);
    status.heading_error_rad = WrapAngleRad(pose_->yaw_rad - std::atan2(t.y(), t.x()));
  }
  const Eigen::Vector2d goal = route_.back();
  status.distance_to_goal_m = (goal - p).norm();
  const double route_left = (route_.size() - 1 - progress_index_) * o.route_spacing_m;
  // Turning at the goal's position goes on unless a fix moved the pose well off it.
  if (turning_since_ && status.distance_to_goal_m > 2.0 * o.goal_tolerance_m) {
    turning_since_.reset();
  }
  if (turning_since_ || GoalReached(status, route_left)) return TurnToGoal(now, dt_s, status);
  if (!progress_since_ || route_left <= least_route_left_m_ - o.no_progress_m) {
    progress_since_ = now;
    least_route_left_m_ = route_left;
  } else if (o.no_progress_timeout_s > 0.0 &&
             DurationSeconds(now, *progress_since_) > o.no_progress_timeout_s) {
    return Abort("no progress for " + FormatFixed(o.no_progress_timeout_s, 0) +
                 " s: " + FormatFixed(route_left, 2) + " m of the route left, " +
                 FormatFixed(status.distance_to_goal_m, 2) + " m from the goal (last: " +
                 (status_.reason.empty() ? std::string(NavigationStateName(status_.state))
                                         : status_.reason) +
                 ")");
  }
  if (grid_.Clearance(goal.x(), goal.y()) < o.robot_radius_m) {
    if (!goal_blocked_since_) goal_blocked_since_ = now;
    if (DurationSeconds(now, *goal_blocked_since_) > o.goal_blocked_timeout_s) {
      return Abort("goal (" + FormatFixed(goal.x(), 2) + ", " + FormatFixed(goal.y(), 2) +
                   ") is inside an obstacle");
    }
  } else {
    goal_blocked_since_.reset();
  }
  const double goal_clearance = grid_.Clearance(goal.x(), goal.y());
  if (goal_clearance < grid_.inflation_m()) {
    // Waiting on an occupied goal: the time the robot stood (commanded) before it since it
    // became so.
    if (std::abs(sent_.linear_mps) < kStandingMps &&
        status.distance_to_goal_m <= o.rejoin_check_m + grid_.inflation_m()) {
      goal_occupied_standing_s_ += dt_s;
    }
    const std::string occupied = "goal (" + FormatFixed(goal.x(), 2) + ", " +
                                 FormatFixed(goal.y(), 2) + ") occupied: an obstacle " +
                                 FormatFixed(goal_clearance, 2) + " m from it";
    if (o.goal_occupied_tolerance_m > 0.0 &&
        status.distance_to_goal_m <= o.goal_occupied_tolerance_m &&
        route_left <= o.goal_occupied_tolerance_m + 0.5) {
      status.state = NavigationState::kReached;
      status.reason =
          occupied + "; reached " + FormatFixed(status.distance_to_goal_m, 2) + " m from it";
      controller_.Reset();
      sent_ = VelocityCommand();
      status_ = status;
      return status_;
    }
    if (o.goal_occupied_timeout_s > 0.0 && goal_occupied_standing_s_ > o.goal_occupied_timeout_s) {
      return Abort(occupied + "; waited " + FormatFixed(goal_occupied_standing_s_, 1) +
                   " s, stopped " + FormatFixed(status.distance_to_goal_m, 2) + " m from it");
    }
  } else {
    goal_occupied_standing_s_ = 0.0;
  }

  UpdatePathChecksRelaxed(now);
  const bool refreshed = RefreshLocalPath(now, &status);
  if (!refreshed && !stalled_since_) stalled_since_ = now;
  if (refreshed) stalled_since_.reset();
  status.path_checks_relaxed = path_checks_relaxed_;
  if (!refreshed) {
    status.state = NavigationState::kSafetyStop;
    status.avoiding = true;  // blocked, no detour yet: still the avoidance manoeuvre
    controller_.Reset();
    GuardCommand(&status);  // standing may not be safe either
    return Finish(now, status);
  }
  status.avoiding = avoiding_;
  // navigator.goal_extension_m: the path extended straight beyond the goal keeps the carrot on
  // the goal's line; the robot brakes to stop just past the goal. Past it (and not reached),
  // the path ends at the goal again and the robot turns back to it.
  const std::vector<Eigen::Vector2d>* path = &local_path_;
  std::vector<Eigen::Vector2d> extended;
  double stop_before_end = 0.0;
  if (o.goal_extension_m > 0.0 && !local_path_.empty() &&
      (local_path_.back() - route_.back()).norm() < 1e-9 && !AbreastOfGoal(p)) {
    extended = local_path_;
    const Eigen::Vector2d dir = GoalDirection();
    const int n = std::max(1, static_cast<int>(std::ceil(o.goal_extension_m / o.route_spacing_m)));
    for (int i = 1; i <= n; ++i) extended.push_back(route_.back() + i * o.route_spacing_m * dir);
    stop_before_end = std::max(0.0, n * o.route_spacing_m - kGoalOvershootM);
    path = &extended;
  }
  // navigator.rejoin_speed_mps: slower until back on the route (by the rejoin rule).
  double speed_cap = std::numeric_limits<double>::infinity();
  if (o.rejoin_speed_mps > 0.0 && !avoiding_ && rejoining_ && !OnRoute(status)) {
    speed_cap = o.rejoin_speed_mps;
  }
  // navigator.approach_overshoot_m: slow enough to turn parallel to the route in time.
  if (o.approach_overshoot_m > 0.0 && !avoiding_ && route_.size() > 1) {
    speed_cap = std::min(speed_cap, ApproachSpeed(status));
  }
  // navigator.stale_fix_distance_m: slower the longer the pose has run on odometry alone.
  status.since_fix_m = since_fix_m_;
  if (o.stale_fix_distance_m > 0.0 && !avoiding_) {
    const TrackingOptions& c = options_.controller;
    const double top = std::max(c.max_speed_mps, c.clear_speed_mps);
    const double cap = StaleFixSpeedCap(since_fix_m_, top, o);
    status.stale_fix_slowed = cap < top;
    speed_cap = std::min(speed_cap, cap);
  }
  // controller.lateral_rate_per_s: the lateral error law steers onto the route itself (from a
  // little behind the robot's projection: the law's curvature window), until back on it by the
  // rejoin rule, or all along it (navigator.lateral_law_on_route).
  // Narrower: not before the first avoidance; only while the rejoining status is raised.
  const bool rejoin_label = rejoining_ && (o.rejoin_max_s <= 0.0 ||
                                           DurationSeconds(now, last_avoiding_) <= o.rejoin_max_s);
  const bool lateral =
      options_.controller.lateral_rate_per_s > 0.0 && route_tracked_ && path == &local_path_ &&
      (o.lateral_law_on_route || rejoining_ || !OnRoute(status)) &&
      (!o.lateral_law_after_avoidance || avoided_) && (!o.lateral_law_rejoin_only || rejoin_label);
  std::vector<Eigen::Vector2d> route_ahead;
  if (lateral) {
    const size_t back =
        static_cast<size_t>(std::ceil(options_.controller.curvature_window_m / o.route_spacing_m));
    route_ahead.assign(
        route_.begin() + static_cast<long>(progress_index_ > back ? progress_index_ - back : 0),
        route_.end());
    path = &route_ahead;
  }
  const TrackingResult tracked =
      controller_.Track(*pose_, *path, &DriveGrid(), dt_s, stop_before_end, speed_cap, lateral);
  status.command = tracked.command;
  if (tracked.safety_stop) {
    status.state = NavigationState::kSafetyStop;
    status.reason = "obstacle within " + FormatFixed(options_.controller.stop_distance_m, 2) +
                    " m ahead of the footprint";
  }
  GuardCommand(&status);
  return Finish(now, status);
}

NavigationStatus Navigator::TurnToGoal(Time now, double dt_s, NavigationStatus status) {
  const NavigatorOptions& o = options_.navigator;
  if (goal_yaw_rad_ && o.goal_yaw_tolerance_rad > 0.0) {
    status.goal_yaw_error_rad = WrapAngleRad(*goal_yaw_rad_ - pose_->yaw_rad);
  }
  if (std::abs(status.goal_yaw_error_rad) <= o.goal_yaw_tolerance_rad) {
    status.state = NavigationState::kReached;
    controller_.Reset();
    sent_ = VelocityCommand();
    status_ = status;
    return status_;
  }
  if (!turning_since_) {
    turning_since_ = now;
    controller_.Reset();  // the drive stops at the position (as when reached), then turns
  }
  const double turning_s = DurationSeconds(now, *turning_since_);
  if (o.no_progress_timeout_s > 0.0 && turning_s > o.no_progress_timeout_s) {
    return Abort("turning to the goal's yaw for " + FormatFixed(turning_s, 0) + " s: still " +
                 FormatFixed(std::abs(status.goal_yaw_error_rad) * 180.0 / M_PI, 1) + " deg off");
  }
  status.state = NavigationState::kTurningToGoal;
  // No translation: the safety stop's zero linear speed holds; the crowd guard still checks
  // the turn against the walkers.
  status.command = controller_.TurnInPlace(status.goal_yaw_error_rad, dt_s);
  GuardCommand(&status);
  return Finish(now, status);
}

double StaleFixSpeedCap(double since_fix_m, double top_speed_mps, const NavigatorOptions& o) {
  const double d0 = o.stale_fix_distance_m;
  if (d0 <= 0.0 || since_fix_m <= d0) return std::numeric_limits<double>::infinity();
  const double slow = std::min(o.stale_fix_speed_mps, top_speed_mps);
  const double f = std::min(1.0, (since_fix_m - d0) / d0);
  return top_speed_mps + f * (slow - top_speed_mps);
}

double Navigator::ApproachSpeed(const NavigationStatus& status) const {
  const NavigatorOptions& o = options_.navigator;
  const double psi = std::min(std::abs(status.heading_error_rad), 0.5 * M_PI);
  const double sideways = 1.0 - std::cos(psi);  // per metre of turning radius
  if (sideways < 1e-9) return std::numeric_limits<double>::infinity();
  const Eigen::Vector2d t = RouteTangent(progress_index_);
  const Eigen::Vector2d n(-t.y(), t.x());
  const double offset = (pose_->position() - route_[progress_index_]).dot(n);  // left positive
  // Heading away from the route (a swerve, a guard's turn) the robot is not slowed: there the
  // cap (room: the margin alone) held it at creeping speed among the walkers.
  if (offset * status.heading_error_rad >= 0.0) return std::numeric_limits<double>::infinity();
  const double room = o.approach_overshoot_m + std::abs(offset);
  return std::max(o.approach_min_speed_mps, o.approach_turn_radps * room / sideways);
}

bool Navigator::OnRoute(const NavigationStatus& status) const {
  return status.cross_track_m <= options_.navigator.rejoin_tolerance_m &&
         (options_.navigator.rejoin_heading_rad <= 0.0 ||
          std::abs(status.heading_error_rad) <= options_.navigator.rejoin_heading_rad) &&
         (options_.navigator.rejoin_turn_radps <= 0.0 ||
          std::abs(status.command.angular_radps) <= options_.navigator.rejoin_turn_radps);
}

const NavigationStatus& Navigator::Finish(Time now, const NavigationStatus& status) {
  status_ = status;
  if (status.avoiding) {
    rejoining_ = true;
    avoided_ = true;
    last_avoiding_ = now;
  } else if (OnRoute(status)) {
    rejoining_ = false;
  }
  // The status's rejoin (the end of the manoeuvre) is bounded in time when asked.
  const bool bounded = options_.navigator.rejoin_max_s > 0.0 &&
                       DurationSeconds(now, last_avoiding_) > options_.navigator.rejoin_max_s;
  status_.rejoining = rejoining_ && !status.avoiding && !bounded;
  return status_;
}

std::optional<Eigen::Vector2d> Navigator::FreeNearGoal(const ObstacleGrid& grid) const {
  const double tolerance = options_.navigator.goal_occupied_tolerance_m;
  if (tolerance <= 0.0 || route_.empty() || !pose_) return std::nullopt;
  const Eigen::Vector2d goal = route_.back();
  const double step = grid.options().resolution_m;
  constexpr int kBearings = 32;
  for (double r = step; r <= tolerance + 1e-9; r += step) {
    std::optional<Eigen::Vector2d> best;
    for (int k = 0; k < kBearings; ++k) {
      const double a = 2.0 * M_PI * k / kBearings;
      const Eigen::Vector2d q = goal + r * Eigen::Vector2d(std::cos(a), std::sin(a));
      if (grid.Occupied(q.x(), q.y())) continue;
      if (!best ||
          (q - pose_->position()).squaredNorm() < (*best - pose_->position()).squaredNorm()) {
        best = q;
      }
    }
    if (best) return best;
  }
  return std::nullopt;
}

void Navigator::GuardCommand(NavigationStatus* status) {
  const GuardResult g = guard_.Check(*pose_, sent_, status->command,
                                     options_.navigator.robot_radius_m, DriveGrid(), tracker_);
  status->predicted_gap_m = g.predicted_gap_m;
  if (g.intervened) {
    status->command = g.command;
    status->yielding = true;
    status->avoiding = true;
    status->guard_action = g.action;
    if (status->reason.empty()) status->reason = "yielding to a walker: " + g.action;
    controller_.SetLastCommand(g.command);
  }
  // A later rule's command replaces the one so far where it differs (`speed_only`: in speed).
  const auto adopt = [&](const VelocityCommand& c, bool* flag, bool speed_only = false) {
    if (c.linear_mps == status->command.linear_mps &&
        (speed_only || c.angular_radps == status->command.angular_radps)) {
      return;
    }
    status->command = c;
    *flag = true;
    controller_.SetLastCommand(c);
  };
  const double radius = options_.navigator.robot_radius_m;
  adopt(guard_.FilterGap(*pose_, status->command, radius, tracker_), &status->gap_filtered);
  adopt(guard_.BlindSideSpeed(*pose_, status->command, radius, tracker_),
        &status->blind_side_slowed, true);
  adopt(guard_.ApproachSpeed(*pose_, status->command, radius, tracker_), &status->approach_slowed,
        true);
  adopt(guard_.Evade(*pose_, sent_, status->command, radius, DriveGrid(), tracker_),
        &status->evaded);
  if (!options_.guard.stopping_with_guard_only || g.intervened) {
    adopt(guard_.BrakeToStopShort(*pose_, sent_, status->command, radius, tracker_),
          &status->stopping_braked);
  }
  sent_ = status->command;
}

}  // namespace icgm
