#include "core/nav/tracking_controller.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace icgm {
namespace {

double Clamp(double v, double lo, double hi) { return std::min(hi, std::max(lo, v)); }

// The point at arc length s of a polyline with cumulative arc lengths `arc` (clamped to its ends).
Eigen::Vector2d PointAtArc(const std::vector<Eigen::Vector2d>& path, const std::vector<double>& arc,
                           double s) {
  if (s <= arc.front()) return path.front();
  if (s >= arc.back()) return path.back();
  const size_t i = std::upper_bound(arc.begin(), arc.end(), s) - arc.begin();  // arc[i] > s
  const double seg = arc[i] - arc[i - 1];
  const double t = seg > 0.0 ? (s - arc[i - 1]) / seg : 0.0;
  return path[i - 1] + (path[i] - path[i - 1]) * t;
}

}  // namespace

TrackingController::TrackingController(TrackingOptions options) : options_(options) {}

bool TrackingController::ObstacleAhead(const Pose2D& pose, const ObstacleGrid& grid) const {
  const double step = 0.5 * grid.options().resolution_m;
  const double half_width = options_.robot_radius_m + options_.stop_corridor_margin_m;
  const double length = options_.robot_radius_m + options_.stop_distance_m;
  for (double x = 0.0; x <= length; x += step) {
    for (double y = -half_width; y <= half_width; y += step) {
      const Eigen::Vector2d p = pose.ToParent(Eigen::Vector2d(x, y));
      if (grid.Obstacle(p.x(), p.y())) return true;
    }
  }
  return false;
}

double NearSpeedCap(double gap_m, const TrackingOptions& options) {
  if (options.near_speed_mps <= 0.0 || gap_m >= options.near_distance_m) {
    return std::numeric_limits<double>::infinity();
  }
  const double f = std::max(0.0, gap_m) / options.near_distance_m;
  return options.near_speed_mps + f * (options.max_speed_mps - options.near_speed_mps);
}

double TrackingController::TopSpeed(const Pose2D& pose, const ObstacleGrid* grid) const {
  if (!grid) return options_.max_speed_mps;
  const double clearance = grid->Clearance(pose.x_m, pose.y_m) - options_.robot_radius_m;
  const double near = std::min(options_.max_speed_mps, NearSpeedCap(clearance, options_));
  if (options_.clear_speed_mps <= options_.max_speed_mps) return near;
  return clearance >= options_.clear_distance_m ? options_.clear_speed_mps : near;
}

double TrackingController::PreviewSpeed(const std::vector<Eigen::Vector2d>& path,
                                        const std::vector<double>& arc_m, double along_m,
                                        double top_speed_mps) const {
  const double window = options_.curvature_window_m;
  const double brake = options_.max_acceleration_mps2;
  const double horizon =
      top_speed_mps * top_speed_mps / (2.0 * brake) +
      std::max(options_.lookahead_min_m, top_speed_mps * options_.lookahead_time_s);
  double limit = std::numeric_limits<double>::infinity();
  // Samples from the robot's own place on, finer than the window (no corner falls between two).
  const double step = std::max(0.01, std::min(0.05, 0.25 * window));
  for (double ahead = 0.0; ahead <= horizon && along_m + ahead <= arc_m.back(); ahead += step) {
    const double s = along_m + ahead;
    const Eigen::Vector2d here = PointAtArc(path, arc_m, s);
    const Eigen::Vector2d back = here - PointAtArc(path, arc_m, s - window);
    const Eigen::Vector2d front = PointAtArc(path, arc_m, s + window) - here;
    if (back.norm() < 0.25 * window || front.norm() < 0.25 * window) continue;  // path's ends
    const double turn =
        std::abs(std::atan2(back.x() * front.y() - back.y() * front.x(), back.dot(front)));
    const double kappa = turn / window;
    if (kappa < 1e-9) continue;
    // Down to the bend's speed a lookahead (at that speed) before it: pure pursuit steers into
    // the bend once its carrot is there.
    const double v_bend2 = options_.max_lateral_acceleration_mps2 / kappa;
    const double lookahead =
        std::max(options_.lookahead_min_m, std::sqrt(v_bend2) * options_.lookahead_time_s);
    const double v2 = v_bend2 + 2.0 * brake * std::max(0.0, ahead - lookahead);
    limit = std::min(limit, std::sqrt(v2));
  }
  return limit;
}

double TrackingController::LateralCurvature(const Pose2D& pose,
                                            const std::vector<Eigen::Vector2d>& path,
                                            const std::vector<double>& arc_m, size_t closest,
                                            double speed_mps) const {
  // The path's direction and curvature over a window around the closest point (smooth at the
  // polyline's vertices).
  const double window = options_.curvature_window_m > 0.0 ? options_.curvature_window_m : 0.5;
  const double s = arc_m[closest];
  const Eigen::Vector2d here = path[closest];
  const Eigen::Vector2d behind = PointAtArc(path, arc_m, s - 0.5 * window);
  const Eigen::Vector2d ahead = PointAtArc(path, arc_m, s + 0.5 * window);
  const Eigen::Vector2d chord = ahead - behind;
  if (chord.norm() < 1e-6) return 0.0;
  const Eigen::Vector2d t = chord.normalized();
  double kappa_path = 0.0;
  const Eigen::Vector2d back = here - behind, front = ahead - here;
  if (back.norm() > 0.25 * window && front.norm() > 0.25 * window) {
    const double turn = std::atan2(back.x() * front.y() - back.y() * front.x(), back.dot(front));
    kappa_path = turn / (0.5 * (back.norm() + front.norm()));
  }
  const Eigen::Vector2d d = pose.position() - here;
  const double e = t.x() * d.y() - t.y() * d.x();  // left of the path: positive
  const double psi = WrapAngleRad(pose.yaw_rad - std::atan2(t.y(), t.x()));
  // Below the law's lowest speed, the curve it steers at that speed (psi_d stays bounded from
  // rest).
  const double v = std::max(options_.lateral_min_speed_mps, speed_mps);
  const double rate = options_.lateral_rate_per_s;
  const double limit = options_.lateral_max_approach_rad;
  double psi_d = -std::atan(rate * e / v);
  // Its change as the offset shrinks (feed-forward of the outer loop), unless it is clamped.
  double psi_d_rate = 0.0;
  if (std::abs(psi_d) < limit) {
    const double e_rate = v * std::sin(psi);
    psi_d_rate = -rate * v / (v * v + rate * rate * e * e) * e_rate;
  } else {
    psi_d = std::copysign(limit, psi_d);
  }
  const double delta = WrapAngleRad(psi_d - psi);
  const double gain = 4.0 * rate;  // the heading loop four times faster: no oscillation
  const double braking = std::sqrt(options_.max_angular_acceleration_radps2 * std::abs(delta));
  const double feedback = std::copysign(std::min(gain * std::abs(delta), braking), delta);
  return kappa_path + (psi_d_rate + feedback) / v;
}

VelocityCommand TrackingController::TurnInPlace(double yaw_error_rad, double dt_s) {
  const double a = options_.max_angular_acceleration_radps2;
  const double rate = std::min(options_.max_angular_radps, std::sqrt(a * std::abs(yaw_error_rad)));
  const double dw = a * dt_s;
  VelocityCommand command;
  command.angular_radps =
      Clamp(std::copysign(rate, yaw_error_rad), last_.angular_radps - dw, last_.angular_radps + dw);
  last_ = command;
  return command;
}

TrackingResult TrackingController::Track(const Pose2D& pose,
                                         const std::vector<Eigen::Vector2d>& path,
                                         const ObstacleGrid* grid, double dt_s,
                                         double stop_before_end_m, double speed_cap_mps,
                                         bool lateral_law) {
  TrackingResult result;
  if (path.empty()) {
    last_ = VelocityCommand();
    return result;
  }
  // Closest path point, and the arc length from it to the end.
  const Eigen::Vector2d p = pose.position();
  size_t closest = 0;
  double best = std::numeric_limits<double>::infinity();
  for (size_t i = 0; i < path.size(); ++i) {
    const double d = (path[i] - p).squaredNorm();
    if (d < best) {
      best = d;
      closest = i;
    }
  }
  double to_end = 0.0;
  for (size_t i = closest + 1; i < path.size(); ++i) to_end += (path[i] - path[i - 1]).norm();
  result.distance_to_end_m = to_end + std::sqrt(best) * (closest + 1 == path.size() ? 1.0 : 0.0);

  // Carrot: lookahead along the path from the closest point.
  const auto point_ahead = [&](double distance_m) {
    double along = 0.0;
    for (size_t i = closest + 1; i < path.size(); ++i) {
      const double seg = (path[i] - path[i - 1]).norm();
      if (along + seg >= distance_m && seg > 0.0) {
        const double s = (distance_m - along) / seg;
        return Eigen::Vector2d(path[i - 1] + (path[i] - path[i - 1]) * s);
      }
      along += seg;
    }
    return path.back();
  };
  const double lookahead =
      std::max(options_.lookahead_min_m, std::abs(last_.linear_mps) * options_.lookahead_time_s);
  result.lookahead_m = lookahead;
  const Eigen::Vector2d carrot = point_ahead(lookahead);
  const Eigen::Vector2d local = pose.ToLocal(carrot);
  const double dist2 = local.squaredNorm();
  const double alpha = std::atan2(local.y(), local.x());

  // Heading away from the path: off it (beyond kAwayMinOffsetM) with the heading error on the
  // offset's side, both taken against the chord from the closest path point to the carrot
  // (the segment's own direction would hold a robot cutting a corner: the carrot is already on
  // the next leg). Turning towards the carrot always ends it.
  bool away = false;
  const Eigen::Vector2d chord = carrot - path[closest];
  if (options_.away_turn_rad > 0.0 && chord.norm() > 0.5 * options_.lookahead_min_m) {
    constexpr double kAwayMinOffsetM = 0.01;
    const Eigen::Vector2d t = chord.normalized();
    const Eigen::Vector2d d = p - path[closest];
    const double offset = t.x() * d.y() - t.y() * d.x();  // left of the chord: positive
    const double psi = WrapAngleRad(pose.yaw_rad - std::atan2(t.y(), t.x()));
    away = std::abs(offset) > kAwayMinOffsetM && offset * psi > 0.0 &&
           std::abs(psi) > options_.away_turn_rad;
  }
  result.turning_back = away;

  double v = 0.0, w = 0.0;
  bool follow_curvature = false;
  double kappa = 0.0;
  if (dist2 < 1e-6) {
    v = 0.0;
    w = 0.0;
  } else if (std::abs(alpha) > options_.turn_in_place_rad || away) {
    w = Clamp(2.0 * alpha, -options_.max_angular_radps, options_.max_angular_radps);
  } else {
    kappa = 2.0 * local.y() / dist2;
    follow_curvature = true;
    v = std::min(TopSpeed(pose, grid), speed_cap_mps);
    result.top_speed_mps = v;
    const bool lateral = lateral_law && options_.lateral_rate_per_s > 0.0 && path.size() > 1;
    // Cumulative arc lengths, for the curvature preview and the lateral law only.
    std::vector<double> arc;
    if (options_.curvature_window_m > 0.0 || lateral) {
      arc.assign(path.size(), 0.0);
      for (size_t i = 1; i < path.size(); ++i) {
        arc[i] = arc[i - 1] + (path[i] - path[i - 1]).norm();
      }
    }
    if (options_.curvature_window_m > 0.0) {
      result.preview_speed_mps = PreviewSpeed(path, arc, arc[closest], v);
      v = std::min(v, result.preview_speed_mps);
    }
    if (lateral) {
      kappa = LateralCurvature(pose, path, arc, closest, std::abs(last_.linear_mps));
      result.lateral_law = true;
    }
    result.curvature_per_m = kappa;
    if (std::abs(kappa) > 1e-9) {
      v = std::min(v, std::sqrt(options_.max_lateral_acceleration_mps2 / std::abs(kappa)));
    }
    v = std::min(v, std::sqrt(2.0 * options_.goal_deceleration_mps2 *
                              std::max(0.0, result.distance_to_end_m - stop_before_end_m)));
    w = v * kappa;
    if (std::abs(w) > options_.max_angular_radps) {
      v *= options_.max_angular_radps / std::abs(w);
      w = std::copysign(options_.max_angular_radps, w);
    }
  }

  // Acceleration limits (a safety stop brakes at once).
  const double dv = options_.max_acceleration_mps2 * dt_s;
  const double dw = options_.max_angular_acceleration_radps2 * dt_s;
  v = Clamp(v, last_.linear_mps - dv, last_.linear_mps + dv);
  if (follow_curvature) {
    w = Clamp(v * kappa, -options_.max_angular_radps, options_.max_angular_radps);
  }
  w = Clamp(w, last_.angular_radps - dw, last_.angular_radps + dw);
  if (grid && ObstacleAhead(pose, *grid)) {
    result.safety_stop = true;
    v = 0.0;
    if (options_.stop_turn_lookahead_m > lookahead) {
      const Eigen::Vector2d far = pose.ToLocal(point_ahead(options_.stop_turn_lookahead_m));
      const double far_alpha = std::atan2(far.y(), far.x());
      const double turn =
          Clamp(2.0 * far_alpha, -options_.max_angular_radps, options_.max_angular_radps);
      w = std::abs(far_alpha) < options_.stop_turn_rad
              ? 0.0
              : Clamp(turn, last_.angular_radps - dw, last_.angular_radps + dw);
    } else if (std::abs(alpha) < options_.stop_turn_rad) {
      w = 0.0;
    }
  }
  result.command.linear_mps = v;
  result.command.angular_radps = w;
  last_ = result.command;
  return result;
}

}  // namespace icgm
