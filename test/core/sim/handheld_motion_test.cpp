// The handheld camera moves like a hand: a slow, smooth drift at the configured mean speed
// within a small region, small rotations around the mean viewing direction, and hand shake
// that stays small from frame to frame.
#include "core/sim/handheld_motion.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <string>

#include "core/common/status.h"
#include "core/dataset/trajectory.h"

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

// A walking person: the camera advances along the mean viewing direction at the walking speed,
// rising and falling with each step and swaying sideways, on top of the standing hand's motion.
TEST(HandheldMotionTest, WalkAdvancesAlongTheViewAtTheWalkingSpeed) {
  HandheldOptions o;
  o.yaw_deg = 60.0;
  o.walk_speed_mps = 1.2;
  Rng rng(4), standing_rng(4);
  const HandheldMotion motion(o, kDuration, rng);
  HandheldOptions standing_options = o;
  standing_options.walk_speed_mps = 0.0;
  const HandheldMotion standing(standing_options, kDuration, standing_rng);
  const Eigen::Vector3d forward(std::cos(o.yaw_deg * kDeg), std::sin(o.yaw_deg * kDeg), 0.0);
  const Eigen::Vector3d left(-forward.y(), forward.x(), 0.0);
  double min_dz = 1.0, max_dz = -1.0, max_side = 0.0;
  for (double t = 0.0; t <= kDuration; t += kDt) {
    const Pose3 T = motion.T_world_camera(t), S = standing.T_world_camera(t);
    const Eigen::Vector3d walk = T.translation() - S.translation();
    SCOPED_TRACE(t);
    EXPECT_NEAR(walk.dot(forward), o.walk_speed_mps * t, 1e-9);
    min_dz = std::min(min_dz, walk.z());
    max_dz = std::max(max_dz, walk.z());
    max_side = std::max(max_side, std::abs(walk.dot(left)));
    EXPECT_LT(Angle(T.linear(), S.linear()), 1e-12);  // the walk does not turn the camera
  }
  EXPECT_NEAR(min_dz, 0.0, 1e-9);
  EXPECT_NEAR(max_dz, o.walk_bob_m, 0.05 * o.walk_bob_m);
  EXPECT_NEAR(max_side, 0.5 * o.walk_bob_m, 0.05 * o.walk_bob_m);
}

// A recorded path replayed: the camera starts at the scenario's pose and then moves, in its own
// frame, exactly as the recording moved relative to its pose recorded_start_s in (between
// recorded poses interpolated, after the last one held); the random motion's options are ignored.
TEST(HandheldMotionTest, RecordedTrajectoryIsReplayedFromTheScenarioPose) {
  const std::string path =
      (std::filesystem::temp_directory_path() / "handheld_motion_test_recorded.txt").string();
  Trajectory recorded;
  for (int k = 0; k <= 20; ++k) {
    StampedPose p;
    p.stamp = Time::FromNanoseconds(1000000000000LL + k * 100000000LL);  // every 0.1 s
    p.pose.linear() =
        Eigen::AngleAxisd(0.02 * k, Eigen::Vector3d(0.1, 1.0, 0.2).normalized()).toRotationMatrix();
    p.pose.translation() = Eigen::Vector3d(5.0 + 0.01 * k, -2.0, 0.003 * k * k);
    recorded.push_back(p);
  }
  WriteTumTrajectory(path, recorded);
  HandheldOptions o;
  o.recorded_trajectory = path;
  o.recorded_start_s = 0.5;
  o.pan_amplitude_deg = 20.0;  // ignored
  Rng rng(3);
  const HandheldMotion motion(o, kDuration, rng);
  const Pose3 start = motion.T_world_camera(0.0);
  EXPECT_NEAR(start.translation().x(), o.x_m, 1e-9);
  EXPECT_NEAR(start.translation().y(), o.y_m, 1e-9);
  EXPECT_NEAR(start.translation().z(), o.height_m, 1e-9);
  // Optical z looks along yaw_deg, pitch_down_deg below the horizon.
  const Eigen::Vector3d forward = start.linear().col(2);
  EXPECT_NEAR(std::atan2(forward.y(), forward.x()), o.yaw_deg * kDeg, 1e-9);
  EXPECT_NEAR(std::asin(-forward.z()), o.pitch_down_deg * kDeg, 1e-9);
  // 0.3 s in: recorded poses 5 (start) and 8, at exact stamps.
  const Pose3 expected = recorded[5].pose.inverse() * recorded[8].pose;
  const Pose3 moved = start.inverse() * motion.T_world_camera(0.3);
  EXPECT_LT((moved.translation() - expected.translation()).norm(), 1e-6);
  EXPECT_LT(Angle(moved.linear(), expected.linear()), 1e-6);
  // Between poses 6 and 7: interpolated, so between them; after the end: the last pose.
  const double between = (start.inverse() * motion.T_world_camera(0.15)).translation().x();
  const double x6 = (recorded[5].pose.inverse() * recorded[6].pose).translation().x();
  const double x7 = (recorded[5].pose.inverse() * recorded[7].pose).translation().x();
  EXPECT_GT(between, std::min(x6, x7));
  EXPECT_LT(between, std::max(x6, x7));
  const Pose3 last = recorded[5].pose.inverse() * recorded.back().pose;
  EXPECT_LT(
      ((start.inverse() * motion.T_world_camera(9.0)).translation() - last.translation()).norm(),
      1e-6);
  // A recording that ends before its start, and a missing file, are load errors.
  o.recorded_start_s = 3.0;
  EXPECT_THROW(HandheldMotion(o, kDuration, rng), LoadError);
  o.recorded_trajectory = path + ".missing";
  o.recorded_start_s = 0.0;
  EXPECT_THROW(HandheldMotion(o, kDuration, rng), LoadError);
  std::filesystem::remove(path);
}

}  // namespace
}  // namespace icgm::sim
