#include "core/sim/loop_route.h"

#include <algorithm>
#include <cmath>

namespace icgm::sim {

LoopRoute::LoopRoute(const RoomOptions& room, const RouteOptions& route)
    : center_(0.5 * room.width_m, 0.5 * room.length_m),
      half_x_m_(0.5 * room.width_m - route.inset_m),
      half_y_m_(0.5 * room.length_m - route.inset_m),
      radius_m_(std::min({route.corner_radius_m, half_x_m_, half_y_m_})),
      speed_mps_(route.speed_mps),
      accel_mps2_(route.acceleration_mps2),
      start_offset_m_(route.start_offset_m) {
  length_m_ =
      4.0 * (half_x_m_ - radius_m_) + 4.0 * (half_y_m_ - radius_m_) + 2.0 * M_PI * radius_m_;
}

PlanarPose LoopRoute::PoseAt(double s_m) const {
  double s = std::fmod(s_m + start_offset_m_, length_m_);
  if (s < 0) s += length_m_;
  const double r = radius_m_;
  const double sx = half_x_m_ - r, sy = half_y_m_ - r;  // half lengths of the straight parts
  const double arc = 0.5 * M_PI * r;
  // Sides in order from the middle of the south side: south (first half), east, north, west,
  // south (second half); a quarter arc follows each of the first four.
  struct Straight {
    double x0, y0, yaw, len;
  };
  const Straight straights[5] = {{center_.x(), center_.y() - half_y_m_, 0.0, sx},
                                 {center_.x() + half_x_m_, center_.y() - sy, 0.5 * M_PI, 2 * sy},
                                 {center_.x() + sx, center_.y() + half_y_m_, M_PI, 2 * sx},
                                 {center_.x() - half_x_m_, center_.y() + sy, 1.5 * M_PI, 2 * sy},
                                 {center_.x() - sx, center_.y() - half_y_m_, 0.0, sx}};
  const Eigen::Vector2d arc_centers[4] = {
      center_ + Eigen::Vector2d(sx, -sy), center_ + Eigen::Vector2d(sx, sy),
      center_ + Eigen::Vector2d(-sx, sy), center_ + Eigen::Vector2d(-sx, -sy)};
  for (int i = 0; i < 5; ++i) {
    const Straight& st = straights[i];
    if (s <= st.len || i == 4) {
      const double d = std::min(s, st.len);
      return {st.x0 + d * std::cos(st.yaw), st.y0 + d * std::sin(st.yaw),
              std::remainder(st.yaw, 2 * M_PI)};
    }
    s -= st.len;
    if (s <= arc) {
      const double a = -0.5 * M_PI + 0.5 * M_PI * i + s / r;
      return {arc_centers[i].x() + r * std::cos(a), arc_centers[i].y() + r * std::sin(a),
              std::remainder(a + 0.5 * M_PI, 2 * M_PI)};
    }
    s -= arc;
  }
  return {};  // unreachable
}

double LoopRoute::DistanceTo(double x_m, double y_m) const {
  // Distance to the boundary of a rounded box (the loop is that boundary).
  const double qx = std::abs(x_m - center_.x()) - (half_x_m_ - radius_m_);
  const double qy = std::abs(y_m - center_.y()) - (half_y_m_ - radius_m_);
  const double outside = std::hypot(std::max(qx, 0.0), std::max(qy, 0.0));
  const double inside = std::min(std::max(qx, qy), 0.0);
  return std::abs(outside + inside - radius_m_);
}

double LoopRoute::ArcLengthAt(double t_s, double duration_s) const {
  const double t = std::clamp(t_s, 0.0, duration_s);
  double v = speed_mps_;
  double ta = v / accel_mps2_;
  if (duration_s < 2 * ta) {
    ta = 0.5 * duration_s;
    v = accel_mps2_ * ta;
  }
  const double total = v * (duration_s - ta);
  if (t < ta) return 0.5 * accel_mps2_ * t * t;
  if (t <= duration_s - ta) return 0.5 * v * ta + v * (t - ta);
  const double rest = duration_s - t;
  return total - 0.5 * accel_mps2_ * rest * rest;
}

double LoopRoute::DurationForLaps(double laps) const {
  return laps * length_m_ / speed_mps_ + speed_mps_ / accel_mps2_;
}

}  // namespace icgm::sim
