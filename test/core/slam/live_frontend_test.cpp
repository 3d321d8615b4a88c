#include "core/slam/live_frontend.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <memory>
#include <string>
#include <vector>

#include "core/features/feature_extractor.h"
#include "core/sim/sim_options.h"
#include "core/sim/simulator.h"
#include "core/slam/slam_options.h"

namespace icgm {
namespace {

constexpr size_t kLiveFrames = 30;

// Rendered static_short frames (10 Hz, one wheel sample per frame at its stamp) with the shipped
// front-end options: the offline front end's poses, and the frames as a live system gets them.
struct LiveRun {
  explicit LiveRun(size_t num_frames = kLiveFrames)
      : sim(sim::LoadSimOptions(std::string(ICGM_SOURCE_DIR) + "/config/sim/static_short.yaml")),
        options(LoadSlamOptions(std::string(ICGM_SOURCE_DIR) + "/config").frontend),
        extractor(FeatureExtractor::Create(options.features)) {
    options.fusion.base_to_camera = sim.T_base_camera();
    for (size_t i = 0; i < num_frames; ++i) frames.push_back(sim.Render(i));
  }
  // As icgm_slam_offline: every wheel sample up to stamp + 50 ms, then ProcessFrame.
  std::vector<Pose3> Offline() const {
    RgbdFrontend frontend(options, sim.intrinsics());
    WheelFeed wheel(0.05);
    for (size_t i = 0; i < frames.size(); ++i) wheel.Add(sim.stamp(i), Wheel(i));
    std::vector<Pose3> poses;
    for (const sim::SimFrame& f : frames) {
      wheel.FeedUpTo(f.stamp, [&](Time t, const Pose3& p) { frontend.AddWheelOdometry(t, p); });
      poses.push_back(frontend.ProcessFrame(f.stamp, f.bgr, f.depth_m).odom_camera);
    }
    return poses;
  }
  LiveFrame Frame(size_t i) const {
    LiveFrame frame;
    frame.stamp = frames[i].stamp;
    frame.features = extractor->Extract(frames[i].bgr);
    frame.depth_m = frames[i].depth_m;
    frame.depth_stamp = frames[i].stamp;
    frame.camera_frame = "camera_rgb_optical_frame";
    return frame;
  }
  Pose3 Wheel(size_t i) const { return sim.odometry(i).T_odom_base; }

  sim::Simulator sim;
  FrontendOptions options;
  std::unique_ptr<FeatureExtractor> extractor;
  std::vector<sim::SimFrame> frames;
};

// Collects what LiveFrontend::Drain reports.
struct LiveOutputs {
  void operator()(const LiveFrameOutput& out) {
    poses.push_back(out.result.odom_camera);
    stamps.push_back(out.frame->stamp);
    if (out.step) steps.push_back(*out.step);
    if (out.new_keyframe) ++keyframes;
    if (out.missing_wheels) ++without_wheels;
  }
  std::vector<Pose3> poses;
  std::vector<Time> stamps;
  std::vector<VisionStepChain::Step> steps;
  int keyframes = 0;
  int without_wheels = 0;
};

// Largest distance between the poses of two runs.
double MaxDifferenceM(const std::vector<Pose3>& a, const std::vector<Pose3>& b) {
  double worst = 0.0;
  for (size_t i = 0; i < a.size() && i < b.size(); ++i) {
    worst = std::max(worst, (a[i].translation() - b[i].translation()).norm());
  }
  return worst;
}

TEST(LiveFrontendTest, FramesBeforeTheirWheelSamplesGiveTheOfflinePoses) {
  LiveRun run;
  const std::vector<Pose3> offline = run.Offline();
  LiveFrontendOptions options;
  options.pacing.max_wait_s = 1.0;  // this test's wall time never ends a wait
  LiveFrontend live(options);
  LiveOutputs outputs;
  const auto sink = [&](const LiveFrameOutput& out) { outputs(out); };
  // Live order: each frame arrives before the wheel sample at its own stamp. The first frame
  // waits for the camera and extrinsic (Start) as well.
  for (size_t i = 0; i < kLiveFrames; ++i) {
    ASSERT_TRUE(live.Push(run.Frame(i)));
    if (i == 2) {
      ASSERT_NE(live.ReadyFront(), nullptr);
      EXPECT_EQ(live.ReadyFront()->camera_frame, "camera_rgb_optical_frame");
      EXPECT_EQ(live.ReadyFront()->stamp, run.frames[0].stamp);
      live.Start(run.options, run.sim.intrinsics());
    }
    live.Drain(sink);
    EXPECT_EQ(outputs.poses.size(), i < 2 ? 0 : i - 1) << "frame " << i << " waits for its wheels";
    ASSERT_TRUE(live.AddWheelOdometry(run.sim.stamp(i), run.Wheel(i)));
    EXPECT_FALSE(live.AddWheelOdometry(run.sim.stamp(i), run.Wheel(i))) << "not newer: dropped";
    live.Drain(sink);
  }
  // The last frame: nothing newer comes, the wait ends (the end of a bag).
  EXPECT_EQ(live.pending(), 1u);
  const Time later = Time::FromNanoseconds(run.sim.stamp(kLiveFrames - 1).nanoseconds() +
                                           2'000'000'000);  // newer data 2 s on
  ASSERT_TRUE(live.AddWheelOdometry(later, run.Wheel(kLiveFrames - 1)));
  live.Drain(sink);
  ASSERT_EQ(outputs.poses.size(), kLiveFrames);
  EXPECT_EQ(outputs.without_wheels, 0);
  for (size_t i = 0; i < kLiveFrames; ++i) {
    EXPECT_EQ(outputs.stamps[i], run.frames[i].stamp);
    EXPECT_LT((outputs.poses[i].translation() - offline[i].translation()).norm(), 1e-9)
        << "frame " << i;
    EXPECT_TRUE(outputs.poses[i].linear().isApprox(offline[i].linear(), 1e-9)) << "frame " << i;
  }
  EXPECT_GE(outputs.keyframes, 2);
  // Every frame after the first gives its step from the one before.
  ASSERT_EQ(outputs.steps.size(), kLiveFrames - 1);
  for (size_t i = 0; i < outputs.steps.size(); ++i) {
    EXPECT_EQ(outputs.steps[i].reference_stamp, run.frames[i].stamp);
    EXPECT_EQ(outputs.steps[i].stamp, run.frames[i + 1].stamp);
    const Pose3 expected = offline[i].inverse() * offline[i + 1];
    EXPECT_LT((outputs.steps[i].result.relative_pose.translation() - expected.translation()).norm(),
              1e-9);
  }
}

TEST(LiveFrontendTest, WithoutPacingTheWheelPriorComesLateAndThePosesDiffer) {
  // The same live order, each frame processed as it arrives (no waiting for its wheel sample):
  // the front end lacks the sample at the frame's stamp, so its poses are not the offline ones.
  // This is what the pacing of the first test prevents.
  LiveRun run;
  const std::vector<Pose3> offline = run.Offline();
  LiveFrontendOptions options;
  options.pacing.wheels = false;
  LiveFrontend live(options);
  live.Start(run.options, run.sim.intrinsics());
  LiveOutputs outputs;
  const auto sink = [&](const LiveFrameOutput& out) { outputs(out); };
  for (size_t i = 0; i < kLiveFrames; ++i) {
    ASSERT_TRUE(live.Push(run.Frame(i)));
    EXPECT_EQ(live.Drain(sink), 1u) << "without wheels a frame is ready at once";
    live.AddWheelOdometry(run.sim.stamp(i), run.Wheel(i));
  }
  ASSERT_EQ(outputs.poses.size(), kLiveFrames);
  EXPECT_GT(MaxDifferenceM(outputs.poses, offline), 1e-6);
}

TEST(LiveFrontendTest, QueueIsBoundedAndClearable) {
  LiveRun run(3);
  LiveFrontendOptions options;
  options.pacing.max_pending = 2;
  LiveFrontend live(options);
  EXPECT_TRUE(live.Push(run.Frame(0)));
  EXPECT_TRUE(live.Push(run.Frame(1)));
  EXPECT_FALSE(live.Push(run.Frame(2))) << "the oldest made room";
  EXPECT_EQ(live.pending(), 2u);
  LiveOutputs outputs;
  EXPECT_EQ(live.Drain([&](const LiveFrameOutput& out) { outputs(out); }), 0u) << "not started";
  live.Clear();
  EXPECT_EQ(live.pending(), 0u);
  EXPECT_EQ(live.ReadyFront(), nullptr);
}

}  // namespace
}  // namespace icgm
