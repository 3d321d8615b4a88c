#include "core/odometry/wheel_odometry_buffer.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "core/common/option_reader.h"

namespace icgm {
namespace {

Time Sec(double s) { return Time::FromNanoseconds(static_cast<int64_t>(std::llround(s * 1e9))); }

// Planar robot pose: x, y in metres, yaw in degrees.
Pose3 Planar(double x, double y, double yaw_deg) {
  return MakePose(Vec3(x, y, 0.0), Quat(Eigen::AngleAxisd(yaw_deg * M_PI / 180.0, Vec3::UnitZ())));
}

bool Contains(const Status& s, const std::string& text) {
  return s.reason().find(text) != std::string::npos;
}

TEST(WheelOdometryBufferTest, InterpolatesRelativeMotion) {
  WheelOdometryBuffer buf;
  // 1 m/s along x, then turning at 20 deg/s.
  for (int i = 0; i <= 10; ++i) ASSERT_TRUE(buf.Add(Sec(0.1 * i), Planar(0.1 * i, 0, 0)).ok());
  Pose3 rel;
  ASSERT_TRUE(buf.RelativeMotion(Sec(0.25), Sec(0.73), &rel).ok());
  EXPECT_NEAR(rel.translation().x(), 0.48, 1e-9);
  EXPECT_NEAR(rel.translation().y(), 0.0, 1e-12);

  WheelOdometryBuffer turn;
  for (int i = 0; i <= 10; ++i) ASSERT_TRUE(turn.Add(Sec(0.1 * i), Planar(0, 0, 2.0 * i)).ok());
  ASSERT_TRUE(turn.RelativeMotion(Sec(0.15), Sec(0.55), &rel).ok());
  EXPECT_NEAR(RotationAngleRad(rel) * 180.0 / M_PI, 8.0, 1e-9);
  Pose3 p;
  ASSERT_TRUE(turn.PoseAt(Sec(1.0), &p).ok());
  EXPECT_NEAR(RotationAngleRad(p) * 180.0 / M_PI, 20.0, 1e-9);
}

TEST(WheelOdometryBufferTest, RefusesTimeGoingBackwards) {
  WheelOdometryBuffer buf;
  ASSERT_TRUE(buf.Add(Sec(1.0), Planar(0, 0, 0)).ok());
  ASSERT_TRUE(buf.Add(Sec(1.1), Planar(0.1, 0, 0)).ok());
  const Status s = buf.Add(Sec(1.05), Planar(0.05, 0, 0));
  EXPECT_FALSE(s.ok());
  EXPECT_TRUE(Contains(s, "time went backwards")) << s.reason();
  EXPECT_FALSE(buf.Add(Sec(1.1), Planar(0.1, 0, 0)).ok());  // duplicate stamp
  EXPECT_EQ(buf.size(), 2u);
  EXPECT_EQ(buf.rejected_samples(), 2u);
  const Pose3 nan_pose = Planar(std::numeric_limits<double>::quiet_NaN(), 0, 0);
  EXPECT_TRUE(Contains(buf.Add(Sec(1.2), nan_pose), "not finite"));
  EXPECT_EQ(buf.size(), 2u);
}

TEST(WheelOdometryBufferTest, DetectsGaps) {
  WheelOdometryOptions opt;
  opt.max_gap_s = 0.5;
  WheelOdometryBuffer buf(opt);
  ASSERT_TRUE(buf.Add(Sec(0.0), Planar(0, 0, 0)).ok());
  ASSERT_TRUE(buf.Add(Sec(0.1), Planar(0.1, 0, 0)).ok());
  ASSERT_TRUE(buf.Add(Sec(1.0), Planar(1.0, 0, 0)).ok());  // 0.9 s gap, plausible speed
  ASSERT_TRUE(buf.Add(Sec(1.1), Planar(1.1, 0, 0)).ok());
  Pose3 rel;
  EXPECT_TRUE(buf.RelativeMotion(Sec(0.0), Sec(0.1), &rel).ok());
  EXPECT_TRUE(buf.RelativeMotion(Sec(1.0), Sec(1.05), &rel).ok());
  // Query inside the gap, and a span over the gap.
  const Status inside = buf.RelativeMotion(Sec(0.05), Sec(0.5), &rel);
  EXPECT_TRUE(Contains(inside, "gap")) << inside.reason();
  const Status across = buf.RelativeMotion(Sec(0.05), Sec(1.05), &rel);
  EXPECT_TRUE(Contains(across, "gap: 0.9 s > 0.5 s")) << across.reason();
}

TEST(WheelOdometryBufferTest, DetectsJumps) {
  WheelOdometryOptions opt;
  opt.max_speed_mps = 2.0;
  opt.max_yaw_rate_dps = 90.0;
  WheelOdometryBuffer buf(opt);
  ASSERT_TRUE(buf.Add(Sec(0.0), Planar(0, 0, 0)).ok());
  ASSERT_TRUE(buf.Add(Sec(0.1), Planar(0.1, 0, 0)).ok());
  const Status jump = buf.Add(Sec(0.2), Planar(5.0, 0, 0));  // 49 m/s: an odometry reset
  EXPECT_TRUE(Contains(jump, "wheel odometry jump: 49 m/s > 2 m/s")) << jump.reason();
  ASSERT_TRUE(buf.Add(Sec(0.3), Planar(5.1, 0, 0)).ok());
  EXPECT_EQ(buf.size(), 4u);
  EXPECT_EQ(buf.jumps_detected(), 1u);
  Pose3 rel;
  EXPECT_TRUE(Contains(buf.RelativeMotion(Sec(0.05), Sec(0.25), &rel), "jump"));
  EXPECT_TRUE(Contains(buf.RelativeMotion(Sec(0.15), Sec(0.18), &rel), "jump"));
  // Both sides of the jump remain usable.
  ASSERT_TRUE(buf.RelativeMotion(Sec(0.0), Sec(0.1), &rel).ok());
  ASSERT_TRUE(buf.RelativeMotion(Sec(0.2), Sec(0.3), &rel).ok());
  EXPECT_NEAR(rel.translation().x(), 0.1, 1e-9);

  const Status spin = buf.Add(Sec(0.4), Planar(5.1, 0, 30.0));  // 300 deg/s
  EXPECT_TRUE(Contains(spin, "yaw rate 300 deg/s > 90 deg/s")) << spin.reason();
}

TEST(WheelOdometryBufferTest, OutsideTheBufferedSpan) {
  WheelOdometryBuffer buf;
  Pose3 p;
  EXPECT_TRUE(Contains(buf.PoseAt(Sec(1.0), &p), "no wheel odometry received"));
  ASSERT_TRUE(buf.Add(Sec(1.0), Planar(0, 0, 0)).ok());
  ASSERT_TRUE(buf.Add(Sec(1.1), Planar(0.1, 0, 0)).ok());
  EXPECT_TRUE(Contains(buf.PoseAt(Sec(0.9), &p), "before the first sample"));
  EXPECT_TRUE(Contains(buf.PoseAt(Sec(1.3), &p), "after the newest sample"));
  // Within the extrapolation allowance (0.05 s) the last velocity is held.
  ASSERT_TRUE(buf.PoseAt(Sec(1.14), &p).ok());
  EXPECT_NEAR(p.translation().x(), 0.14, 1e-9);
}

TEST(WheelOdometryBufferTest, TrimKeepsInterpolationSupport) {
  WheelOdometryBuffer buf;
  for (int i = 0; i <= 10; ++i) ASSERT_TRUE(buf.Add(Sec(0.1 * i), Planar(0.1 * i, 0, 0)).ok());
  buf.TrimBefore(Sec(0.55));
  EXPECT_EQ(buf.oldest(), Sec(0.5));
  Pose3 p;
  EXPECT_TRUE(buf.PoseAt(Sec(0.55), &p).ok());
  EXPECT_FALSE(buf.PoseAt(Sec(0.45), &p).ok());
}

TEST(WheelOdometryBufferTest, ReadsOptions) {
  WheelOdometryOptions opt;
  ReadOptions(OptionReader::FromString("max_gap_s: 0.2\nmax_speed_mps: 1.5\n"), &opt);
  EXPECT_EQ(opt.max_gap_s, 0.2);
  EXPECT_EQ(opt.max_speed_mps, 1.5);
  EXPECT_THROW(ReadOptions(OptionReader::FromString("max_gap_s: -1\n"), &opt), LoadError);
}

}  // namespace
}  // namespace icgm
