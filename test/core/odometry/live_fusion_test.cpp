#include "core/odometry/live_fusion.h"

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

namespace icgm {
namespace {

Time LiveSec(double s) {
  return Time::FromNanoseconds(static_cast<int64_t>(std::llround(s * 1e9)));
}

// The base drives along x at 0.5 m/s and turns at 0.2 rad/s; camera = base (identity extrinsic).
Pose3 LiveAt(double s) {
  return MakePose(Vec3(0.5 * s, 0.0, 0.0), Quat(Eigen::AngleAxisd(0.2 * s, Vec3::UnitZ())));
}

RegistrationResult LiveVision(double from_s, double to_s) {
  RegistrationResult r;
  r.status = Status::Ok();
  r.relative_pose = LiveAt(from_s).inverse() * LiveAt(to_s);
  return r;
}

TEST(LiveFusionTest, ResultsWaitForTheStartAndFuseFromTheFirstReference) {
  LiveFusion live(FusionOptions{}, WheelOdometryOptions{}, FusionQueueOptions{});
  EXPECT_FALSE(live.Start(Pose3::Identity()).has_value()) << "nothing to start from";
  EXPECT_FALSE(live.started());
  for (int i = 0; i <= 8; ++i) {
    ASSERT_TRUE(live.AddWheelOdometry(LiveSec(1.0 + 0.05 * i), LiveAt(1.0 + 0.05 * i)).ok());
  }
  // Results arrive while the extrinsic is unknown: they wait.
  live.Push(LiveSec(1.1), LiveSec(1.0), LiveVision(1.0, 1.1));
  live.Push(LiveSec(1.2), LiveSec(1.1), LiveVision(1.1, 1.2));
  std::vector<Time> fused;
  const auto on_fused = [&](const FusedResult& r) {
    fused.push_back(r.stamp);
    EXPECT_EQ(r.step.source, MotionSource::kVision);
  };
  std::vector<Time> dropped;
  const auto on_dropped = [&](Time t) { dropped.push_back(t); };
  live.Drain(on_fused, on_dropped);
  EXPECT_TRUE(fused.empty()) << "not started";
  EXPECT_EQ(live.waiting(), 2u);

  const std::optional<Time> start = live.Start(Pose3::Identity());
  ASSERT_TRUE(start.has_value());
  EXPECT_EQ(*start, LiveSec(1.0)) << "the first result's reference frame";
  live.Push(LiveSec(1.3), LiveSec(1.2), LiveVision(1.2, 1.3));
  live.Drain(on_fused, on_dropped);
  ASSERT_EQ(fused.size(), 3u);
  EXPECT_EQ(fused[0], LiveSec(1.1));
  EXPECT_EQ(fused[2], LiveSec(1.3));
  // Started at the wheel pose of 1.0 s, then the vision steps: the base's pose at 1.3 s.
  EXPECT_TRUE(live.fusion()->odom_base().isApprox(LiveAt(1.3), 1e-9));

  live.Push(LiveSec(1.25), LiveSec(1.2), LiveVision(1.2, 1.25));  // time went backwards
  live.Drain(on_fused, on_dropped);
  ASSERT_EQ(dropped.size(), 1u);
  EXPECT_EQ(dropped[0], LiveSec(1.25));
  EXPECT_EQ(fused.size(), 3u);
}

TEST(LiveFusionTest, TheStartTakesTheGivenExtrinsicAndClearDropsTheWaitingResults) {
  LiveFusion live(FusionOptions{}, WheelOdometryOptions{}, FusionQueueOptions{});
  for (int i = 0; i <= 4; ++i) {
    ASSERT_TRUE(live.AddWheelOdometry(LiveSec(0.05 * i), LiveAt(0.05 * i)).ok());
  }
  live.Push(LiveSec(0.1), LiveSec(0.0), LiveVision(0.0, 0.1));
  live.Clear();
  EXPECT_EQ(live.waiting(), 0u);
  EXPECT_FALSE(live.Start(Pose3::Identity()).has_value()) << "cleared: nothing to start from";

  const Pose3 base_to_camera = MakePose(Vec3(0.1, 0.0, 0.5), Quat::Identity());
  live.Push(LiveSec(0.2), LiveSec(0.1), LiveVision(0.1, 0.2));
  ASSERT_EQ(live.Start(base_to_camera), LiveSec(0.1));
  EXPECT_TRUE(live.fusion()->options().base_to_camera.isApprox(base_to_camera, 1e-12));
  // The camera starts where the wheels put the base at 0.1 s, through the extrinsic.
  EXPECT_TRUE(live.fusion()->odom_base().isApprox(LiveAt(0.1), 1e-9));
}

}  // namespace
}  // namespace icgm
