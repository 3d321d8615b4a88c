// Path tracking for a differential-drive base: pure pursuit on the local path (the carrot a
// speed-dependent lookahead ahead of the closest path point), speed limited by the path's
// curvature (lateral acceleration; at the carrot, and optionally previewed along the path over
// the braking distance, curvature_window_m), by the distance left to the path's end (braking)
// and by acceleration limits relative to the previous command. Turns in place when the carrot
// lies far off the heading. Safety stop: an obstacle (a person) inside the footprint's corridor
// within stop_distance_m ahead gives zero linear speed at once, flagged; the robot may only turn
// in place towards a carrot that lies off the blocked corridor (so that it can take a detour;
// optionally a carrot farther along the path, stop_turn_lookahead_m). Optionally (away_turn_rad)
// a robot off the path and heading away from it brakes and turns in place before driving on.
#pragma once

#include <limits>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "core/common/velocity_command.h"
#include "core/nav/obstacle_grid.h"
#include "core/nav/planar_pose.h"

namespace icgm {

struct TrackingOptions {
  double max_speed_mps = 0.8;
  double max_angular_radps = 1.0;
  double max_acceleration_mps2 = 0.8;
  double max_angular_acceleration_radps2 = 2.0;
  double max_lateral_acceleration_mps2 = 0.6;  // curvature slowdown: v^2 * |k| <= this
  double lookahead_min_m = 0.25;
  double lookahead_time_s = 0.8;         // lookahead = max(min, speed * this)
  double turn_in_place_rad = 1.0;        // carrot further off the heading: rotate only
  double goal_deceleration_mps2 = 0.5;   // braking to stop at the path's end
  double stop_distance_m = 0.35;         // safety corridor ahead of the footprint's front
  double stop_corridor_margin_m = 0.05;  // the corridor's half width is radius + this
  double robot_radius_m = 0.25;
  double stop_turn_rad = 0.35;  // stopped, the robot may still turn towards a carrot this far off
  // Stopped, the turn is aimed at the path this far ahead (when longer than the lookahead): a
  // detour that squeezes past the obstacle before bending away starts almost straight ahead,
  // and the near carrot would keep the robot facing the obstacle. Turning in place keeps a
  // circular footprint where it is. 0: the carrot (off).
  double stop_turn_lookahead_m = 0.0;
  // Speed profile: where nothing is near (no obstacle cell, people included, within
  // clear_distance_m of the footprint) the top speed is this instead of max_speed_mps; the
  // curvature, braking and acceleration limits still apply. 0: off (max_speed_mps everywhere).
  double clear_speed_mps = 1.0;
  double clear_distance_m = 1.5;
  // Slower near obstacles: where the nearest cell (people and furniture alike) is within
  // near_distance_m of the footprint, the top speed falls linearly from max_speed_mps there to
  // near_speed_mps at contact, so that the robot passes people it comes close to slowly enough
  // for the safety stop and the crowd guard to hold it off in time. 0: off.
  double near_speed_mps = 0.0;
  double near_distance_m = 0.5;
  // Curvature preview: the path's curvature ahead limits the speed where the robot is. A sample's
  // curvature k is its heading change between the chords of this length behind and ahead of it
  // divided by this length (1/R on an arc of radius R; a polyline corner of angle a counts as
  // a / this). Pure pursuit steers into a bend once its carrot gets there, so the robot must be
  // down to the bend's speed v_k = sqrt(max_lateral_acceleration_mps2 / k) a lookahead L(v_k)
  // before it: v^2 <= v_k^2 + 2 max_acceleration_mps2 max(0, s - L(v_k)) for every sample s
  // ahead within the braking distance from the top speed (plus its lookahead). The curvature at
  // the carrot alone notices a sharp bend too late at a high speed. 0: off.
  double curvature_window_m = 0.5;
  // Turning back before driving on: when the robot is off the path and heads away from it (its
  // heading and its offset on the same side of the path's direction at the closest point) by
  // more than this, it brakes and turns in place towards the carrot, as when the carrot lies
  // beyond turn_in_place_rad: driving on would take it farther off while it turns back (the
  // pursuit arc bulges outwards). 0: off.
  double away_turn_rad = 0.0;
  // Lateral error law (0: off, pure pursuit), used when Track is asked for it (the navigator's
  // route, navigator.lateral_law_on_route): the path's curvature at the closest point as
  // feed-forward plus a heading loop towards the approach angle psi_d = -atan(rate * e / v)
  // (e: the signed offset from the path, v: the speed), so that the offset decays as
  // exp(-rate * t) and the robot enters the path tangentially instead of crossing it at an
  // angle (pure pursuit's swing grows with the approach angle times the lookahead). The heading
  // loop's turn rate is bounded by the braking curve sqrt(max_angular_acceleration_radps2 *
  // |psi_d - psi|) (half the limit: the rate must be unwound in time), so that the heading does
  // not swing past psi_d. The approach angle is at most lateral_max_approach_rad.
  double lateral_rate_per_s = 0.0;
  double lateral_max_approach_rad = 0.6;
  // Gain scheduling at low speed: below this speed the law steers the curve it would steer at
  // this speed (the approach angle and the heading loop computed at it, the curvature divided
  // by it), so that a creeping robot turns onto the route over the same distance instead of
  // turning at the loop's full rate in place.
  double lateral_min_speed_mps = 0.1;
};

struct TrackingResult {
  VelocityCommand command;
  bool safety_stop = false;
  double lookahead_m = 0.0;
  double curvature_per_m = 0.0;
  double top_speed_mps = 0.0;      // max_speed_mps, or clear_speed_mps where nothing is near
  double distance_to_end_m = 0.0;  // along the path from the closest point
  // The curvature preview's limit (infinity when off, nothing bends ahead or turning in place).
  double preview_speed_mps = std::numeric_limits<double>::infinity();
  bool turning_back = false;  // TrackingOptions::away_turn_rad: turning in place
  bool lateral_law = false;   // TrackingOptions::lateral_rate_per_s steered this step
};

// TrackingOptions::near_speed_mps: the top speed with the nearest cell gap_m from the
// footprint (infinity when off or beyond near_distance_m).
double NearSpeedCap(double gap_m, const TrackingOptions& options);

class TrackingController {
 public:
  explicit TrackingController(TrackingOptions options = TrackingOptions());

  // One control step of dt_s: the command that follows `path` (map frame, start .. end) from
  // `pose`; `grid` may be null (no safety stop). Remembers the command for the acceleration
  // limits. The robot brakes to stop `stop_before_end_m` before the path's end (0: at the end;
  // a path extended beyond its goal keeps the carrot on the goal's line while the robot stops
  // at the goal). `speed_cap_mps` caps the top speed for this step (the navigator's rejoin).
  // `lateral_law`: steer by the lateral error law (when lateral_rate_per_s > 0) instead of the
  // pursuit arc; speed limits, turning in place and the safety stop as for pure pursuit.
  TrackingResult Track(const Pose2D& pose, const std::vector<Eigen::Vector2d>& path,
                       const ObstacleGrid* grid, double dt_s, double stop_before_end_m = 0.0,
                       double speed_cap_mps = std::numeric_limits<double>::infinity(),
                       bool lateral_law = false);
  // One control step of dt_s turning in place (zero linear speed) by yaw_error_rad (target yaw
  // minus heading, wrapped): the turn rate within max_angular_radps, on the braking curve
  // sqrt(max_angular_acceleration_radps2 * |error|) (half the limit: the rate is unwound in time
  // with a discrete step), and changed from the previous command by at most the angular
  // acceleration. Remembers the command.
  VelocityCommand TurnInPlace(double yaw_error_rad, double dt_s);
  // True when an obstacle lies in the corridor ahead of the footprint.
  bool ObstacleAhead(const Pose2D& pose, const ObstacleGrid& grid) const;
  // Forgets the previous command (stop: the next command starts from rest).
  void Reset() { last_ = VelocityCommand(); }
  // The command actually sent when something else (the crowd guard) replaced this one's: the
  // acceleration limits continue from it.
  void SetLastCommand(const VelocityCommand& command) { last_ = command; }
  const VelocityCommand& last_command() const { return last_; }
  const TrackingOptions& options() const { return options_; }

 private:
  // max_speed_mps, or clear_speed_mps where the grid is clear around the footprint.
  double TopSpeed(const Pose2D& pose, const ObstacleGrid* grid) const;
  // The curvature preview's speed limit for a robot at arc length `along_m` of `path`
  // (cumulative arc lengths `arc_m`), braking from `top_speed_mps`.
  double PreviewSpeed(const std::vector<Eigen::Vector2d>& path, const std::vector<double>& arc_m,
                      double along_m, double top_speed_mps) const;
  // The lateral error law's curvature for a robot at `pose` driving at `speed_mps`, `closest`
  // being its nearest path point (arc lengths `arc_m`).
  double LateralCurvature(const Pose2D& pose, const std::vector<Eigen::Vector2d>& path,
                          const std::vector<double>& arc_m, size_t closest, double speed_mps) const;

  TrackingOptions options_;
  VelocityCommand last_;
};

}  // namespace icgm
