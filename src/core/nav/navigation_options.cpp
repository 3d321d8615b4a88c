#include "core/nav/navigation_options.h"

namespace icgm {

void ReadNavigationOptions(const OptionReader& root, NavigationOptions* options) {
  const OptionReader nav = root.Section("navigator");
  NavigatorOptions& n = options->navigator;
  nav.Read("robot_radius_m", &n.robot_radius_m, 0.05, 2.0);
  nav.Read("goal_tolerance_m", &n.goal_tolerance_m, 0.01, 5.0);
  nav.Read("omega", &n.omega, 1, 1000);
  nav.Read("lookahead_m", &n.lookahead_m, 0.1, 10.0);
  nav.Read("route_spacing_m", &n.route_spacing_m, 0.005, 1.0);
  nav.Read("replan_period_s", &n.replan_period_s, 0.0, 10.0);
  nav.Read("rejoin_check_m", &n.rejoin_check_m, 0.1, 20.0);
  nav.Read("detour_delay_s", &n.detour_delay_s, 0.0, 60.0);
  nav.Read("max_goal_off_map_m", &n.max_goal_off_map_m, 0.0, 100.0);
  nav.Read("max_localization_age_s", &n.max_localization_age_s, 0.01, 3600.0);
  nav.Read("max_depth_age_s", &n.max_depth_age_s, 0.01, 3600.0);
  nav.Read("goal_blocked_timeout_s", &n.goal_blocked_timeout_s, 0.0, 3600.0);
  nav.Read("pointer_search_m", &n.pointer_search_m, 0.1, 100.0);
  nav.Read("no_progress_timeout_s", &n.no_progress_timeout_s, 0.0, 36000.0);
  nav.Read("no_progress_m", &n.no_progress_m, 0.01, 100.0);
  nav.Read("rejoin_tolerance_m", &n.rejoin_tolerance_m, 0.001, 10.0);
  nav.Read("rejoin_heading_rad", &n.rejoin_heading_rad, 0.0, 3.2);
  nav.Read("rejoin_turn_radps", &n.rejoin_turn_radps, 0.0, 10.0);
  nav.Read("merge_distance_m", &n.merge_distance_m, 0.0, 10.0);
  nav.Read("goal_line_tolerance_m", &n.goal_line_tolerance_m, 0.0, 1.0);
  nav.Read("goal_extension_m", &n.goal_extension_m, 0.0, 5.0);
  nav.Read("goal_yaw_tolerance_rad", &n.goal_yaw_tolerance_rad, 0.0, 3.2);
  nav.Read("detour_join_m", &n.detour_join_m, 0.0, 10.0);
  nav.Read("rejoin_dubins_radius_m", &n.rejoin_dubins_radius_m, 0.0, 5.0);
  nav.Read("rejoin_max_s", &n.rejoin_max_s, 0.0, 3600.0);
  nav.Read("rejoin_speed_mps", &n.rejoin_speed_mps, 0.0, 3.0);
  nav.Read("approach_overshoot_m", &n.approach_overshoot_m, 0.0, 1.0);
  nav.Read("approach_turn_radps", &n.approach_turn_radps, 0.05, 5.0);
  nav.Read("approach_min_speed_mps", &n.approach_min_speed_mps, 0.0, 3.0);
  nav.Read("stale_fix_distance_m", &n.stale_fix_distance_m, 0.0, 100.0);
  nav.Read("stale_fix_speed_mps", &n.stale_fix_speed_mps, 0.01, 3.0);
  nav.Read("lateral_law_on_route", &n.lateral_law_on_route);
  nav.Read("lateral_law_after_avoidance", &n.lateral_law_after_avoidance);
  nav.Read("lateral_law_rejoin_only", &n.lateral_law_rejoin_only);
  nav.Read("walker_sweep_s", &n.walker_sweep_s, 0.0, 10.0);
  nav.Read("walker_sweep_step_s", &n.walker_sweep_step_s, 0.05, 2.0);
  nav.Read("goal_occupied_tolerance_m", &n.goal_occupied_tolerance_m, 0.0, 2.0);
  nav.Read("goal_occupied_timeout_s", &n.goal_occupied_timeout_s, 0.0, 3600.0);
  nav.Read("scan_tracker_only", &n.scan_tracker_only);
  nav.Read("walker_cells_ahead_only", &n.walker_cells_ahead_only);
  nav.Read("walker_cells_near_m", &n.walker_cells_near_m, 0.0, 10.0);
  nav.Read("walker_cell_margin_m", &n.walker_cell_margin_m, 0.0, 1.0);
  nav.Read("forget_walker_trail", &n.forget_walker_trail);
  nav.Read("walker_bodies_in_grid", &n.walker_bodies_in_grid);
  nav.Read("walker_bodies_path_checks", &n.walker_bodies_path_checks);
  nav.Read("path_checks_inflated", &n.path_checks_inflated);
  nav.Read("path_checks_inflated_route_only", &n.path_checks_inflated_route_only);
  nav.Read("path_check_clearance_m", &n.path_check_clearance_m, -1.0, 2.0);
  nav.Read("path_checks_relax_after_s", &n.path_checks_relax_after_s, 0.0, 60.0);
  nav.Read("path_checks_relax_for_s", &n.path_checks_relax_for_s, 0.1, 60.0);
  nav.Read("path_checks_relax_plan_clearance_m", &n.path_checks_relax_plan_clearance_m, -1.0, 2.0);

  const OptionReader grid = root.Section("obstacle_grid");
  ObstacleGridOptions& g = options->obstacle_grid;
  grid.Read("resolution_m", &g.resolution_m, 0.01, 1.0);
  grid.Read("size_m", &g.size_m, 1.0, 50.0);
  grid.Read("min_height_m", &g.min_height_m, 0.0, 3.0);
  grid.Read("max_height_m", &g.max_height_m, 0.05, 5.0);
  grid.Read("max_range_m", &g.max_range_m, 0.3, 20.0);
  grid.Read("voxel_size_m", &g.voxel_size_m, 0.005, 1.0);
  grid.Read("pixel_step", &g.pixel_step, 1, 32);
  grid.Read("min_points_per_cell", &g.min_points_per_cell, 1, 1000);
  grid.Read("memory_s", &g.memory_s, 0.0, 3600.0);
  grid.Read("clearance_m", &g.clearance_m, 0.0, 5.0);
  if (g.max_height_m <= g.min_height_m) {
    throw LoadError("obstacle_grid.max_height_m must exceed obstacle_grid.min_height_m");
  }

  const OptionReader planner = root.Section("local_planner");
  LocalPlannerOptions& p = options->local_planner;
  planner.Read("window_m", &p.window_m, 1.0, 50.0);
  planner.Read("max_state_checks", &p.max_state_checks, 100, 10000000);
  planner.Read("simplify_steps", &p.simplify_steps, 0, 10000);
  planner.Read("time_cap_ms", &p.time_cap_ms, 1.0, 10000.0);
  planner.Read("range_m", &p.range_m, 0.05, 10.0);
  planner.Read("check_resolution_m", &p.check_resolution_m, 0.005, 0.5);
  planner.Read("sample_spacing_m", &p.sample_spacing_m, 0.005, 1.0);
  planner.Read("start_escape_m", &p.start_escape_m, 0.0, 5.0);
  planner.Read("seed", &p.seed, 1, 1 << 30);

  const OptionReader controller = root.Section("controller");
  TrackingOptions& c = options->controller;
  controller.Read("max_speed_mps", &c.max_speed_mps, 0.01, 3.0);
  controller.Read("max_angular_radps", &c.max_angular_radps, 0.05, 10.0);
  controller.Read("max_acceleration_mps2", &c.max_acceleration_mps2, 0.01, 10.0);
  controller.Read("max_angular_acceleration_radps2", &c.max_angular_acceleration_radps2, 0.01,
                  50.0);
  controller.Read("max_lateral_acceleration_mps2", &c.max_lateral_acceleration_mps2, 0.01, 10.0);
  controller.Read("lookahead_min_m", &c.lookahead_min_m, 0.02, 5.0);
  controller.Read("lookahead_time_s", &c.lookahead_time_s, 0.0, 10.0);
  controller.Read("turn_in_place_rad", &c.turn_in_place_rad, 0.1, 3.2);
  controller.Read("goal_deceleration_mps2", &c.goal_deceleration_mps2, 0.01, 10.0);
  controller.Read("stop_distance_m", &c.stop_distance_m, 0.0, 5.0);
  controller.Read("stop_corridor_margin_m", &c.stop_corridor_margin_m, 0.0, 2.0);
  controller.Read("stop_turn_rad", &c.stop_turn_rad, 0.0, 3.2);
  controller.Read("stop_turn_lookahead_m", &c.stop_turn_lookahead_m, 0.0, 5.0);
  controller.Read("clear_speed_mps", &c.clear_speed_mps, 0.0, 3.0);
  controller.Read("clear_distance_m", &c.clear_distance_m, 0.0, 10.0);
  controller.Read("near_speed_mps", &c.near_speed_mps, 0.0, 3.0);
  controller.Read("near_distance_m", &c.near_distance_m, 0.01, 5.0);
  controller.Read("curvature_window_m", &c.curvature_window_m, 0.0, 5.0);
  controller.Read("away_turn_rad", &c.away_turn_rad, 0.0, 3.2);
  controller.Read("lateral_rate_per_s", &c.lateral_rate_per_s, 0.0, 20.0);
  controller.Read("lateral_max_approach_rad", &c.lateral_max_approach_rad, 0.05, 1.5);
  controller.Read("lateral_min_speed_mps", &c.lateral_min_speed_mps, 0.01, 2.0);

  const OptionReader tracker = root.Section("walker_tracker");
  ObstacleTrackerOptions& t = options->tracker;
  tracker.Read("link_distance_m", &t.link_distance_m, 0.01, 1.0);
  tracker.Read("max_cluster_radius_m", &t.max_cluster_radius_m, 0.05, 5.0);
  tracker.Read("min_radius_m", &t.min_radius_m, 0.0, 2.0);
  tracker.Read("gate_m", &t.gate_m, 0.05, 5.0);
  tracker.Read("history_s", &t.history_s, 0.05, 10.0);
  tracker.Read("track_timeout_s", &t.track_timeout_s, 0.0, 30.0);
  tracker.Read("min_observations", &t.min_observations, 2, 100);
  tracker.Read("moving_speed_mps", &t.moving_speed_mps, 0.0, 5.0);
  tracker.Read("max_speed_mps", &t.max_speed_mps, 0.1, 10.0);
  tracker.Read("standing_hold_s", &t.standing_hold_s, 0.0, 60.0);
  tracker.Read("standing_hold_min_frames", &t.standing_hold_min_frames, 1, 1000);
  tracker.Read("body_offset_m", &t.body_offset_m, 0.0, 1.0);
  tracker.Read("body_radius_m", &t.body_radius_m, 0.0, 2.0);
  tracker.Read("reidentify_s", &t.reidentify_s, 0.0, 60.0);
  tracker.Read("reidentify_gate_m", &t.reidentify_gate_m, 0.05, 3.0);
  tracker.Read("robust_velocity", &t.robust_velocity);
  tracker.Read("side_memory_s", &t.side_memory_s, 0.0, 60.0);
  tracker.Read("side_memory_damping_s", &t.side_memory_damping_s, 0.0, 10.0);
  tracker.Read("side_memory_growth_mps", &t.side_memory_growth_mps, 0.0, 2.0);
  tracker.Read("side_memory_keeps_moving", &t.side_memory_keeps_moving);

  const OptionReader guard = root.Section("crowd_guard");
  CrowdGuardOptions& q = options->guard;
  guard.Read("horizon_s", &q.horizon_s, 0.0, 10.0);
  guard.Read("step_s", &q.step_s, 0.01, 1.0);
  guard.Read("min_gap_m", &q.min_gap_m, -1.0, 2.0);
  guard.Read("caution_gap_m", &q.caution_gap_m, -1.0, 3.0);
  guard.Read("acceleration_mps2", &q.acceleration_mps2, 0.01, 10.0);
  guard.Read("angular_acceleration_radps2", &q.angular_acceleration_radps2, 0.01, 50.0);
  guard.Read("reverse_speed_mps", &q.reverse_speed_mps, 0.0, 3.0);
  guard.Read("swerve_speed_mps", &q.swerve_speed_mps, 0.0, 3.0);
  guard.Read("turn_radps", &q.turn_radps, 0.0, 10.0);
  guard.Read("standing_walkers", &q.standing_walkers);
  guard.Read("gap_filter_m", &q.gap_filter_m, 0.0, 2.0);
  guard.Read("gap_filter_horizon_s", &q.gap_filter_horizon_s, 0.05, 5.0);
  guard.Read("unseen_walkers", &q.unseen_walkers);
  guard.Read("blind_side_speed_mps", &q.blind_side_speed_mps, 0.0, 3.0);
  guard.Read("blind_side_gap_m", &q.blind_side_gap_m, 0.0, 3.0);
  guard.Read("evasive_gap_m", &q.evasive_gap_m, 0.0, 2.0);
  guard.Read("evasive_horizon_s", &q.evasive_horizon_s, 0.1, 5.0);
  guard.Read("evasive_reverse_mps", &q.evasive_reverse_mps, 0.0, 1.0);
  guard.Read("walker_personal_space_m", &q.walker_personal_space_m, 0.0, 2.0);
  guard.Read("stopping_gap_m", &q.stopping_gap_m, 0.0, 2.0);
  guard.Read("stopping_deceleration_mps2", &q.stopping_deceleration_mps2, 0.05, 10.0);
  guard.Read("stopping_reaction_s", &q.stopping_reaction_s, 0.0, 2.0);
  guard.Read("stopping_margin_s", &q.stopping_margin_s, 0.0, 2.0);
  guard.Read("stopping_with_guard_only", &q.stopping_with_guard_only);
  guard.Read("body_gap_m", &q.body_gap_m, 0.0, 2.0);
  guard.Read("body_horizon_s", &q.body_horizon_s, 0.1, 10.0);
  guard.Read("body_creep_speed_mps", &q.body_creep_speed_mps, 0.0, 2.0);
  guard.Read("body_creep_gap_m", &q.body_creep_gap_m, 0.0, 2.0);
  guard.Read("body_all_tracks", &q.body_all_tracks);
  guard.Read("own_motion_only", &q.own_motion_only);
  guard.Read("approach_gap_m", &q.approach_gap_m, 0.0, 3.0);
  guard.Read("approach_rate_per_s", &q.approach_rate_per_s, 0.0, 100.0);
  guard.Read("approach_near_m", &q.approach_near_m, 0.0, 5.0);
  guard.Read("approach_all_tracks", &q.approach_all_tracks);
  guard.Read("remembered_gap_m", &q.remembered_gap_m, 0.0, 2.0);
  guard.Read("remembered_horizon_s", &q.remembered_horizon_s, 0.1, 5.0);
  guard.Read("remembered_near_m", &q.remembered_near_m, 0.0, 5.0);
  guard.Read("remembered_alternatives_only", &q.remembered_alternatives_only);

  OptionReader::RejectUnknownKeys({&nav, &grid, &planner, &controller, &tracker, &guard, &root});
  g.robot_radius_m = n.robot_radius_m;
  c.robot_radius_m = n.robot_radius_m;
}

NavigationOptions LoadNavigationOptions(const std::string& path) {
  NavigationOptions options;
  ReadNavigationOptions(OptionReader::FromFile(path), &options);
  return options;
}

}  // namespace icgm
