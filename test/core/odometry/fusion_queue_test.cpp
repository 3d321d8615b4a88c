#include "core/odometry/fusion_queue.h"

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

namespace icgm {
namespace {

Time Sec(double s) { return Time::FromNanoseconds(static_cast<int64_t>(std::llround(s * 1e9))); }

// The base drives along x at 0.5 m/s; camera = base (identity extrinsic).
Pose3 At(double s) { return MakePose(Vec3(0.5 * s, 0.0, 0.0), Quat::Identity()); }

RegistrationResult Vision(double from_s, double to_s) {
  RegistrationResult r;
  r.status = Status::Ok();
  r.relative_pose = At(from_s).inverse() * At(to_s);
  return r;
}

RegistrationResult Failed() {
  RegistrationResult r;
  r.status = Status::Error("too few inliers");
  return r;
}

struct FusionRun {
  explicit FusionRun(double wheel_to_s) {
    AddWheel(0.0, wheel_to_s);
    fusion.Initialize(Sec(0.0), &wheel);
  }
  void AddWheel(double from_s, double to_s) {
    for (double s = from_s; s <= to_s + 1e-9; s += 0.05) EXPECT_TRUE(wheel.Add(Sec(s), At(s)).ok());
  }
  void Drain(FusionQueue* queue) {
    queue->Drain(
        &fusion, wheel,
        [&](const FusedResult& r) {
          fused.push_back(r.stamp);
          sources.push_back(r.step.source);
          EXPECT_EQ(r.registration->status.ok(), r.step.source == MotionSource::kVision);
        },
        [&](Time t) { dropped.push_back(t); });
  }
  WheelOdometryBuffer wheel;
  OdometryFusion fusion;
  std::vector<Time> fused, dropped;
  std::vector<MotionSource> sources;
};

TEST(FusionQueueTest, FailedRegistrationWaitsForWheelDataCoveringItsStamp) {
  FusionRun run(0.2);
  FusionQueue queue;  // waits up to 0.3 s of message time
  queue.Push(Sec(0.1), Vision(0.0, 0.1));
  run.Drain(&queue);
  ASSERT_EQ(run.fused.size(), 1u);
  EXPECT_EQ(run.sources[0], MotionSource::kVision);

  queue.Push(Sec(0.3), Failed());
  run.Drain(&queue);
  EXPECT_EQ(run.fused.size(), 1u) << "waits: the wheels have not reached 0.3 s";
  run.AddWheel(0.25, 0.35);
  run.Drain(&queue);
  ASSERT_EQ(run.fused.size(), 2u);
  EXPECT_EQ(run.sources[1], MotionSource::kWheel);
  EXPECT_TRUE(run.fusion.odom_base().isApprox(At(0.3), 1e-9)) << "the wheels' motion to 0.3 s";

  // No wheel data comes any more: the failed result waits until a result 0.3 s later.
  queue.Push(Sec(0.5), Failed());
  queue.Push(Sec(0.7), Vision(0.5, 0.7));
  run.Drain(&queue);
  EXPECT_EQ(run.fused.size(), 2u);
  queue.Push(Sec(0.9), Vision(0.7, 0.9));
  run.Drain(&queue);
  ASSERT_EQ(run.fused.size(), 5u);
  EXPECT_EQ(run.fused[2], Sec(0.5));
  EXPECT_EQ(run.fused[3], Sec(0.7));
  EXPECT_EQ(run.fused[4], Sec(0.9));
  EXPECT_TRUE(queue.empty());

  // Time going backwards: dropped, the fused pose unchanged.
  const Pose3 before = run.fusion.odom_base();
  queue.Push(Sec(0.8), Vision(0.7, 0.8));
  run.Drain(&queue);
  ASSERT_EQ(run.dropped.size(), 1u);
  EXPECT_EQ(run.dropped[0], Sec(0.8));
  EXPECT_EQ(run.fused.size(), 5u);
  EXPECT_TRUE(run.fusion.odom_base().isApprox(before, 1e-12));
}

TEST(FusionQueueTest, TooManyWaitingResultsAreFusedWithoutWaiting) {
  FusionRun run(0.1);
  FusionQueueOptions options;
  options.max_wait_for_wheel_s = 100.0;
  options.max_pending = 3;
  FusionQueue queue(options);
  for (int i = 1; i <= 3; ++i) {
    queue.Push(Sec(0.1 + 0.1 * i), Failed());
    run.Drain(&queue);
  }
  EXPECT_TRUE(run.fused.empty()) << "3 results wait for wheel data";
  queue.Push(Sec(0.5), Failed());
  run.Drain(&queue);
  EXPECT_EQ(run.fused.size(), 4u) << "the fourth: all fused";
  EXPECT_TRUE(queue.empty());
}

}  // namespace
}  // namespace icgm
