// The handheld camera moves like a hand: a slow, smooth drift at the configured mean speed
// within a small region, small rotations around the mean viewing direction, and hand shake
// that stays small from frame to frame.
#include "core/sim/handheld_motion.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include <Eigen/Geometry>

namespace icgm::sim {
namespace {

constexpr double kDeg = M_PI / 180.0;
constexpr double kDuration = 10.0, kDt = 1.0 / 30.0;

double Angle(const Eigen::Matrix3d& a, const Eigen::Matrix3d& b) {
  return Eigen::AngleAxisd(a.transpose() * b).angle();
}

TEST(HandheldMotionTest, DriftHasTheMeanSpeedAndStaysInASmallRegion) {
  HandheldOptions o;
  o.jitter_m = 0.0;
  o.jitter_deg = 0.0;
  Rng rng(7);
  const HandheldMotion motion(o, kDuration, rng);
  const Eigen::Vector3d start(o.x_m, o.y_m, o.height_m);
  EXPECT_LT((motion.T_world_camera(0.0).translation() - start).norm(), 1e-12);
  double path = 0.0, max_offset = 0.0, max_dz = 0.0;
  for (double t = 0.0; t < kDuration; t += kDt) {
    const Eigen::Vector3d p = motion.T_world_camera(t).translation();
    path += (motion.T_world_camera(t + kDt).translation() - p).norm();
    max_offset = std::max(max_offset, (p - start).norm());
    max_dz = std::max(max_dz, std::abs(p.z() - start.z()));
  }
  EXPECT_NEAR(path / kDuration, o.drift_speed_mps, 0.1 * o.drift_speed_mps);
  // About speed * period / 4 from the start, a few times that at most.
  EXPECT_LT(max_offset, o.drift_speed_mps * o.drift_period_s);
  EXPECT_GT(max_offset, 0.02);
  EXPECT_LT(max_dz, 0.1);
}

TEST(HandheldMotionTest, MotionIsSmoothWithSmallRotationsAndShake) {
  const HandheldOptions o;  // with hand shake
  for (int seed = 1; seed <= 5; ++seed) {
    Rng rng(seed);
    const HandheldMotion motion(o, kDuration, rng);
    const Eigen::Matrix3d mean_view =
        (Eigen::AngleAxisd(o.yaw_deg * kDeg, Eigen::Vector3d::UnitZ()) *
         Eigen::AngleAxisd(o.pitch_down_deg * kDeg, Eigen::Vector3d::UnitY()))
            .toRotationMatrix();
    double max_step_m = 0.0, max_step_rad = 0.0, max_accel_m = 0.0, max_off_view = 0.0;
    for (double t = kDt; t < kDuration; t += kDt) {
      const Pose3 a = motion.T_world_camera(t - kDt), b = motion.T_world_camera(t),
                  c = motion.T_world_camera(t + kDt);
      max_step_m = std::max(max_step_m, (c.translation() - b.translation()).norm());
      max_step_rad = std::max(max_step_rad, Angle(b.linear(), c.linear()));
      max_accel_m = std::max(
          max_accel_m, (a.translation() - 2.0 * b.translation() + c.translation()).norm());
      // The optical axis stays within the pan/tilt amplitudes (plus shake) of the mean view.
      const Eigen::Vector3d forward = b.linear().col(2), mean_forward = mean_view.col(0);
      max_off_view = std::max(max_off_view, std::acos(std::clamp(forward.dot(mean_forward), -1.0,
                                                                 1.0)));
    }
    SCOPED_TRACE(seed);
    EXPECT_LT(max_step_m, 0.3 * kDt);        // below 30 cm/s
    EXPECT_LT(max_step_rad, 40 * kDeg * kDt);  // below 40 deg/s
    EXPECT_LT(max_accel_m, 0.002);           // no jumps between frames
    EXPECT_LT(max_off_view,
              (o.pan_amplitude_deg + o.tilt_amplitude_deg + 2.0 * o.jitter_deg) * kDeg);
    // Optical frame: y (down) points below the horizon, x (right) stays nearly level.
    const Pose3 T = motion.T_world_camera(1.0);
    EXPECT_LT(T.linear().col(1).z(), 0.0);
    EXPECT_LT(std::abs(T.linear().col(0).z()), std::sin((o.roll_amplitude_deg + 1.0) * kDeg));
  }
}

TEST(HandheldMotionTest, ViewOnFloorIsTheCameraPositionAndHorizontalViewingDirection) {
  HandheldOptions o;
  o.yaw_deg = 30.0;
  Rng rng(3);
  const HandheldMotion motion(o, kDuration, rng);
  const Pose3 T = motion.T_world_camera(2.0);
  const PlanarPose p = motion.ViewOnFloor(2.0);
  EXPECT_DOUBLE_EQ(p.x_m, T.translation().x());
  EXPECT_DOUBLE_EQ(p.y_m, T.translation().y());
  EXPECT_NEAR(p.yaw_rad, 30.0 * kDeg, (o.pan_amplitude_deg + o.jitter_deg) * kDeg);
}

}  // namespace
}  // namespace icgm::sim
