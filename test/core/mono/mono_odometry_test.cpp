// Monocular odometry on a short clip rendered by the simulator (colour only; depth ignored):
// the trajectory must match the ground truth up to a similarity (Sim(3) ATE bound), the wheel
// odometry must give the metric scale, and blank frames must make it lose track, drop the map,
// initialize again and carry on.
#include <cstdio>
#include <memory>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "core/dataset/trajectory.h"
#include "core/mono/mono_evaluation.h"
#include "core/mono/mono_odometry.h"
#include "core/sim/sim_export.h"
#include "core/sim/simulator.h"

namespace icgm {
namespace {

constexpr size_t kFrames = 90;

// The clip, rendered once for all tests: the start of config/sim/static_short.yaml (a robot
// driving along the cafeteria, no pedestrians).
struct Clip {
  std::unique_ptr<sim::Simulator> sim;
  std::vector<sim::SimFrame> frames;
};

const Clip& GetClip() {
  static const Clip clip = [] {
    Clip c;
    c.sim = std::make_unique<sim::Simulator>(
        sim::LoadSimOptions(std::string(ICGM_SOURCE_DIR) + "/config/sim/static_short.yaml"));
    for (size_t i = 0; i < kFrames && i < c.sim->size(); ++i) c.frames.push_back(c.sim->Render(i));
    return c;
  }();
  return clip;
}

struct ClipRun {
  Trajectory estimate;
  std::vector<MonoFrameResult> results;
  size_t resets = 0;
};

// `blank`: frames [blank_from, blank_to) replaced by black images.
ClipRun RunClip(bool wheels, size_t blank_from = 0, size_t blank_to = 0) {
  const Clip& clip = GetClip();
  MonoOdometry vo(MonoOptions(), clip.sim->intrinsics());
  if (wheels) vo.SetBaseToCamera(*clip.sim->base_to_camera());
  ClipRun run;
  for (const sim::SimFrame& f : clip.frames) {
    if (wheels) {
      EXPECT_TRUE(vo.AddWheelOdometry(f.stamp, f.odometry.T_odom_base).ok());
    }
    const bool blank = f.index >= blank_from && f.index < blank_to;
    const cv::Mat image = blank ? cv::Mat(f.bgr.size(), CV_8UC3, cv::Scalar::all(0)) : f.bgr;
    const MonoFrameResult r = vo.ProcessFrame(f.stamp, image);
    if (r.initialized) run.estimate.push_back({r.reference_stamp, r.reference_world_camera});
    if (r.has_pose) run.estimate.push_back({r.stamp, r.world_camera});
    run.resets += r.reset;
    run.results.push_back(r);
  }
  SortByStamp(&run.estimate);
  return run;
}

Trajectory Truth() {
  const Clip& clip = GetClip();
  Trajectory t;
  for (const sim::SimFrame& f : clip.frames) t.push_back({f.stamp, f.T_world_camera});
  return t;
}

TEST(MonoOdometryTest, TracksRenderedClipWithinSim3Bound) {
  const ClipRun run = RunClip(false);
  size_t tracked = 0;
  for (const auto& r : run.results) tracked += r.has_pose;
  EXPECT_GT(tracked, 0.8 * kFrames);
  EXPECT_EQ(run.resets, 0u);
  for (const auto& r : run.results) EXPECT_FALSE(r.scale_known);
  MonoEvaluation eval;
  ASSERT_TRUE(EvaluateMonoTrajectory(Truth(), run.estimate, 0.01, &eval).ok());
  std::printf("rendered clip, no wheels: %zu/%zu frames tracked, Sim(3) ATE %.4f m over %.2f m "
              "(%.2f%%)\n", tracked, kFrames, eval.evaluation.ate.rmse, eval.distance_m,
              eval.error_percent);
  EXPECT_GT(eval.distance_m, 1.0);
  EXPECT_LT(eval.error_percent, 3.0);
}

TEST(MonoOdometryTest, WheelOdometryGivesTheMetricScale) {
  const ClipRun run = RunClip(true);
  ASSERT_FALSE(run.results.empty());
  EXPECT_TRUE(run.results.back().scale_known);
  MonoEvaluation eval;
  ASSERT_TRUE(EvaluateMonoTrajectory(Truth(), run.estimate, 0.01, &eval).ok());
  std::printf("rendered clip, wheels: Sim(3) scale %.3f m per unit, ATE %.4f m\n", eval.scale,
              eval.evaluation.ate.rmse);
  EXPECT_NEAR(eval.scale, 1.0, 0.1);
}

TEST(MonoOdometryTest, BlankFramesLoseTrackAndReinitialize) {
  const size_t from = 40, to = 46;
  const ClipRun run = RunClip(false, from, to);
  EXPECT_EQ(run.resets, 1u);
  for (size_t i = from; i < to; ++i) {
    EXPECT_FALSE(run.results[i].has_pose) << i;
    EXPECT_FALSE(run.results[i].status.ok()) << i;
  }
  EXPECT_EQ(run.results[to - 1].state, MonoState::kInitializing);
  // Initialized again within a second of images, and tracking to the end.
  size_t reinit = 0;
  for (size_t i = to; i < kFrames; ++i) {
    if (run.results[i].initialized) reinit = i;
  }
  ASSERT_GT(reinit, 0u) << "never re-initialized";
  EXPECT_LT(reinit, to + 30);
  EXPECT_EQ(run.results.back().state, MonoState::kTracking);
  // The pieces after the loss on their own match the truth up to a similarity.
  Trajectory after;
  for (const auto& p : run.estimate) {
    if (p.stamp >= run.results[to].stamp) after.push_back(p);
  }
  MonoEvaluation eval;
  ASSERT_TRUE(EvaluateMonoTrajectory(Truth(), after, 0.01, &eval).ok());
  EXPECT_LT(eval.error_percent, 5.0);
  // The carried-over scale keeps the whole trajectory close to one similarity.
  MonoEvaluation whole;
  ASSERT_TRUE(EvaluateMonoTrajectory(Truth(), run.estimate, 0.01, &whole).ok());
  std::printf("blank frames %zu-%zu: re-initialized at frame %zu; Sim(3) error after %.2f%%, "
              "whole %.2f%% of %.2f m\n", from, to - 1, reinit, eval.error_percent,
              whole.error_percent, whole.distance_m);
  EXPECT_LT(whole.error_percent, 15.0);
}

TEST(MonoOdometryTest, BadImagesAreErrorsNotExceptions) {
  MonoOdometry vo{MonoOptions(), CameraIntrinsics()};
  EXPECT_FALSE(vo.ProcessFrame(Time::FromSeconds(1.0), cv::Mat()).status.ok());
  EXPECT_FALSE(vo.ProcessFrame(Time::FromSeconds(2.0), cv::Mat(480, 640, CV_32FC1, 0.5f)).status.ok());
  EXPECT_EQ(vo.state(), MonoState::kInitializing);
}

}  // namespace
}  // namespace icgm
