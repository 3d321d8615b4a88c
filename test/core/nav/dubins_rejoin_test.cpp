#include "core/nav/dubins_rejoin.h"

#include <cmath>

#include <gtest/gtest.h>

namespace icgm {
namespace {

TEST(DubinsRejoinTest, SettlingArcEndsTheTurnAtTheAccelerationLimit) {
  // Turning at 0.8 rad/s at 0.2 m/s, the turn rate brought to zero at 2 rad/s^2: 0.4 s, the
  // heading turns on by w^2 / 2a = 0.16 rad over 8 cm.
  std::vector<Eigen::Vector2d> arc;
  const Pose2D end = TurnSettlingArc(Pose2D{0, 0, 0}, 0.2, 0.8, 2.0, 0.05, &arc);
  EXPECT_NEAR(end.yaw_rad, 0.16, 1e-9);
  ASSERT_EQ(arc.size(), 8u);
  double length = (arc.front() - Eigen::Vector2d(0, 0)).norm();
  for (size_t i = 1; i < arc.size(); ++i) length += (arc[i] - arc[i - 1]).norm();
  EXPECT_NEAR(length, 0.08, 1e-3);
  EXPECT_GT(end.y_m, 0.0);  // it went on turning left
  EXPECT_NEAR((arc.back() - end.position()).norm(), 0.0, 1e-12);
  // Turning right: the mirror image; no turn: no arc.
  const Pose2D right = TurnSettlingArc(Pose2D{0, 0, 0}, 0.2, -0.8, 2.0, 0.05, &arc);
  EXPECT_NEAR(right.yaw_rad, -0.16, 1e-9);
  EXPECT_NEAR(right.y_m, -end.y_m, 1e-12);
  const Pose2D still = TurnSettlingArc(Pose2D{1, 2, 0.3}, 0.2, 0.0, 2.0, 0.05, &arc);
  EXPECT_TRUE(arc.empty());
  EXPECT_EQ(still.x_m, 1.0);
}

// Heading of the polyline between samples i-1 and i.
double SegmentHeading(const std::vector<Eigen::Vector2d>& c, size_t i) {
  const Eigen::Vector2d d = c[i] - c[i - 1];
  return std::atan2(d.y(), d.x());
}

TEST(DubinsRejoinTest, CurveArrivesAlongTheTargetWithBoundedTurns) {
  double length = 0.0;
  // Along a straight line: the line itself.
  std::vector<Eigen::Vector2d> c = DubinsCurve({0, 0, 0}, {2, 0, 0}, 0.4, 0.05, &length);
  EXPECT_NEAR(length, 2.0, 1e-9);
  for (const auto& q : c) EXPECT_NEAR(q.y(), 0.0, 1e-9);
  // From 0.3 m beside the line, along it, to a point on it 1.5 m ahead: an S-curve that comes
  // down onto the line without crossing it, arrives along it and turns no tighter than 0.4 m.
  c = DubinsCurve({0, 0.3, 0}, {1.5, 0, 0}, 0.4, 0.05, &length);
  EXPECT_GT(length, 1.5);
  EXPECT_LT(length, 1.7);
  EXPECT_NEAR(c.front().y(), 0.3, 1e-9);
  EXPECT_NEAR((c.back() - Eigen::Vector2d(1.5, 0)).norm(), 0.0, 1e-9);
  for (size_t i = 1; i < c.size(); ++i) {
    EXPECT_GT(c[i].y(), -1e-6);
    EXPECT_LT((c[i] - c[i - 1]).norm(), 0.05 + 1e-9);
  }
  // The last chord of an arc of radius 0.4 m over 5 cm is 0.0625 rad off its end tangent.
  EXPECT_NEAR(SegmentHeading(c, c.size() - 1), 0.0, 0.5 * 0.05 / 0.4 + 1e-3);
  for (size_t i = 2; i < c.size(); ++i) {
    const double turn = std::abs(WrapAngleRad(SegmentHeading(c, i) - SegmentHeading(c, i - 1)));
    const double ds = 0.5 * ((c[i] - c[i - 1]).norm() + (c[i - 1] - c[i - 2]).norm());
    EXPECT_LT(turn / ds, 1.0 / 0.4 + 0.05) << i;
  }
  // Heading away from the line (0.5 rad, 5 cm beside it): it must turn back first; the curve
  // goes out by r (1 - cos 0.5) = 4.9 cm at most before it comes back.
  c = DubinsCurve({0, 0.05, 0.5}, {1.5, 0, 0}, 0.4, 0.05, &length);
  double farthest = 0.0;
  for (const auto& q : c) farthest = std::max(farthest, q.y());
  EXPECT_GT(farthest, 0.05 + 0.03);
  EXPECT_LT(farthest, 0.05 + 0.4 * (1.0 - std::cos(0.5)) + 1e-3);
}

TEST(DubinsRejoinTest, CurveWhoseFirstArcIsAlmostAFullTurn) {
  // A rejoin met in the crowd benchmark: 3.6 cm beside the route heading along it, a join point
  // 0.67 m ahead. OMPL's solver alone aborts the process here (its first arc is 3.9e-7 rad
  // short of a full turn); the curve must come out and end at the target.
  const Pose2D from{3.8290727332749936, -0.035622658778528882, -0.0014205671548848109};
  const Pose2D to{4.4965986913965548, -0.036480651536176502, -0.043852788412260202};
  double length = 0.0;
  const std::vector<Eigen::Vector2d> c = DubinsCurve(from, to, 0.1, 0.05, &length);
  ASSERT_GE(c.size(), 2u);
  EXPECT_NEAR(length, (to.position() - from.position()).norm(), 0.01);
  EXPECT_LT((c.back() - to.position()).norm(), 1e-9);
  EXPECT_LT((c.front() - from.position()).norm(), 1e-9);
}

}  // namespace
}  // namespace icgm
