// The route is a closed, smooth loop driven with a bounded speed profile.
#include "core/sim/loop_route.h"

#include <gtest/gtest.h>

#include <cmath>

namespace icgm::sim {
namespace {

RoomOptions Room20() {
  RoomOptions room;
  room.width_m = 20.0;
  room.length_m = 16.0;
  return room;
}

RouteOptions Route() {
  RouteOptions r;
  r.inset_m = 2.5;
  r.corner_radius_m = 2.0;
  r.speed_mps = 0.5;
  r.acceleration_mps2 = 0.25;
  return r;
}

TEST(LoopRouteTest, LengthMatchesRoundedRectangle) {
  const LoopRoute route(Room20(), Route());
  // Straight parts 2 * (15 - 4) + 2 * (11 - 4), plus one full circle of radius 2.
  EXPECT_NEAR(route.length_m(), 2 * 11.0 + 2 * 7.0 + 2 * M_PI * 2.0, 1e-9);
}

TEST(LoopRouteTest, PosesLieOnTheLoopAndHeadAlongIt) {
  const LoopRoute route(Room20(), Route());
  const double step = 0.01;
  for (double s = 0.0; s < route.length_m(); s += 0.37) {
    const PlanarPose a = route.PoseAt(s);
    const PlanarPose b = route.PoseAt(s + step);
    EXPECT_NEAR(route.DistanceTo(a.x_m, a.y_m), 0.0, 1e-9) << "s=" << s;
    // Unit speed along the arc length, heading along the motion.
    EXPECT_NEAR(std::hypot(b.x_m - a.x_m, b.y_m - a.y_m), step, 1e-5) << "s=" << s;
    const double motion_yaw = std::atan2(b.y_m - a.y_m, b.x_m - a.x_m);
    EXPECT_NEAR(std::remainder(motion_yaw - a.yaw_rad, 2 * M_PI), 0.0, 0.01) << "s=" << s;
  }
  // Starts at the middle of the south side heading +x, stays inside the room, closes.
  const PlanarPose start = route.PoseAt(0.0);
  EXPECT_NEAR(start.x_m, 10.0, 1e-9);
  EXPECT_NEAR(start.y_m, 2.5, 1e-9);
  EXPECT_NEAR(start.yaw_rad, 0.0, 1e-9);
  const PlanarPose end = route.PoseAt(route.length_m());
  EXPECT_NEAR(end.x_m, start.x_m, 1e-9);
  EXPECT_NEAR(end.y_m, start.y_m, 1e-9);
}

TEST(LoopRouteTest, DistanceToMeasuresOffsetFromTheLoop) {
  const LoopRoute route(Room20(), Route());
  EXPECT_NEAR(route.DistanceTo(10.0, 1.0), 1.5, 1e-9);  // outside the south side
  EXPECT_NEAR(route.DistanceTo(10.0, 8.0), 5.5, 1e-9);  // centre: nearest sides are south/north
}

TEST(LoopRouteTest, SpeedProfileStartsAndEndsAtRestWithinLimits) {
  const LoopRoute route(Room20(), Route());
  const double duration = route.DurationForLaps(2.0);
  EXPECT_DOUBLE_EQ(route.ArcLengthAt(0.0, duration), 0.0);
  EXPECT_NEAR(route.ArcLengthAt(duration, duration), 2.0 * route.length_m(), 1e-9);
  const double dt = 0.05;
  double prev = 0.0, max_speed = 0.0;
  for (double t = dt; t <= duration; t += dt) {
    const double s = route.ArcLengthAt(t, duration);
    EXPECT_GE(s, prev);
    max_speed = std::max(max_speed, (s - prev) / dt);
    prev = s;
  }
  EXPECT_NEAR(max_speed, 0.5, 1e-6);
  EXPECT_LT(route.ArcLengthAt(dt, duration) / dt, 0.05);  // accelerates from rest
}

}  // namespace
}  // namespace icgm::sim
