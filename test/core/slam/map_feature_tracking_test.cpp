#include "core/slam/map_feature_tracking.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "core/icgm/robust_feature_tracker.h"
#include "core/odometry/rgbd_frontend.h"
#include "core/sim/sim_options.h"
#include "core/sim/simulator.h"
#include "core/slam/slam_options.h"

namespace icgm {
namespace {

constexpr size_t kFrames = 30;

// Rendered static_short frames through a front end with the shipped options and wheels.
struct FrontendRun {
  FrontendRun()
      : sim(sim::LoadSimOptions(std::string(ICGM_SOURCE_DIR) + "/config/sim/static_short.yaml")),
        options(LoadSlamOptions(std::string(ICGM_SOURCE_DIR) + "/config")) {
    options.frontend.fusion.base_to_camera = sim.T_base_camera();
    options.map_features.tracker.mode = TrackerMode::kDouble;
    options.map_features.tracker.window_size = 3;
  }
  // A front end with the run's options; *made gets each keyframe it makes.
  std::unique_ptr<RgbdFrontend> Frontend(KeyframePtr* made) const {
    auto frontend = std::make_unique<RgbdFrontend>(options.frontend, sim.intrinsics());
    frontend->SetKeyframeCallback([made](const KeyframePtr& k) { *made = k; });
    return frontend;
  }
  // Frame i (its wheel sample first) through `frontend`; *made: its keyframe or null, *stamp
  // (when given): the frame's stamp. False when the front end refuses the wheel sample.
  bool Process(size_t i, RgbdFrontend* frontend, KeyframePtr* made, Time* stamp = nullptr) {
    if (!frontend->AddWheelOdometry(sim.stamp(i), sim.odometry(i).T_odom_base).ok()) return false;
    const sim::SimFrame f = sim.Render(i);
    if (stamp != nullptr) *stamp = f.stamp;
    made->reset();
    frontend->ProcessFrame(f.stamp, f.bgr, f.depth_m);
    return true;
  }
  sim::Simulator sim;
  SlamOptions options;
};

TEST(MapFeatureTrackingTest, ReferenceKeyframeSourcePassesEachKeyframeAtOnce) {
  FrontendRun run;
  run.options.map_features.source = MapFeatureSource::kReferenceKeyframe;
  KeyframePtr made;
  const std::unique_ptr<RgbdFrontend> frontend = run.Frontend(&made);
  MapFeatureTracking tracking(run.options.map_features);
  EXPECT_FALSE(tracking.holds_keyframes());
  int released = 0;
  for (size_t i = 0; i < std::min(run.sim.size(), kFrames); ++i) {
    Time stamp;
    ASSERT_TRUE(run.Process(i, frontend.get(), &made, &stamp));
    const KeyframePtr expected = made;
    const std::optional<FrontendKeyframe> k = tracking.AfterFrame(*frontend, std::move(made));
    ASSERT_EQ(k.has_value(), expected != nullptr) << "frame " << i;
    if (!k) continue;
    ++released;
    EXPECT_EQ(k->stamp, stamp);
    EXPECT_EQ(k->robust, expected->robust) << "the registration's flags";
  }
  EXPECT_GE(released, 3);
  EXPECT_FALSE(tracking.Flush().has_value());
}

TEST(MapFeatureTrackingTest, TrackerSourceReleasesEachKeyframeAfterItsNextFrame) {
  FrontendRun run;
  run.options.map_features.source = MapFeatureSource::kTracker;
  KeyframePtr made;
  const std::unique_ptr<RgbdFrontend> frontend = run.Frontend(&made);
  MapFeatureTracking tracking(run.options.map_features);
  EXPECT_TRUE(tracking.holds_keyframes());
  // A tracker of its own over the same frames' features: the flags each frame should get.
  RobustFeatureTracker reference(run.options.map_features.tracker);
  std::map<int64_t, std::vector<uint8_t>> robust_at;
  const auto keep = [&](const std::optional<TrackedFrame>& t) {
    if (t) robust_at[t->stamp.nanoseconds()] = t->robust;
  };
  std::vector<Time> stamps;
  std::vector<FrontendKeyframe> made_all, released;
  const size_t frames = std::min(run.sim.size(), kFrames);
  for (size_t i = 0; i < frames; ++i) {
    Time frame_stamp;
    ASSERT_TRUE(run.Process(i, frontend.get(), &made, &frame_stamp));
    stamps.push_back(frame_stamp);
    Time stamp;
    const FeatureSet* features = frontend->last_frame_features(&stamp);
    ASSERT_NE(features, nullptr);
    keep(reference.AddFeatures(stamp, *features));
    if (made) made_all.push_back(*made);
    const bool had_held = tracking.holding();
    if (std::optional<FrontendKeyframe> k = tracking.AfterFrame(*frontend, std::move(made))) {
      ASSERT_TRUE(had_held);
      ASSERT_GE(i, 1u);
      EXPECT_EQ(k->stamp, stamps[i - 1]) << "released with the frame after its own";
      released.push_back(*k);
    }
    // The same frame again (a frame the front end dropped): nothing is fed twice.
    EXPECT_FALSE(tracking.AfterFrame(*frontend, nullptr).has_value());
  }
  keep(reference.Flush());
  const bool last_held = tracking.holding();
  if (std::optional<FrontendKeyframe> k = tracking.Flush()) {
    EXPECT_TRUE(last_held);
    EXPECT_EQ(k->stamp, stamps.back());
    released.push_back(*k);
  }
  EXPECT_FALSE(tracking.holding());
  EXPECT_FALSE(tracking.Flush().has_value());

  ASSERT_GE(made_all.size(), 3u);
  ASSERT_EQ(released.size(), made_all.size()) << "every keyframe is released once";
  int differing = 0;
  for (size_t k = 0; k < released.size(); ++k) {
    const FrontendKeyframe& a = made_all[k];
    const FrontendKeyframe& b = released[k];
    EXPECT_EQ(a.stamp, b.stamp);
    ASSERT_EQ(a.features.size(), b.features.size()) << "the keyframe's own features";
    EXPECT_EQ(a.odom_camera.matrix(), b.odom_camera.matrix());
    ASSERT_TRUE(robust_at.count(b.stamp.nanoseconds()));
    EXPECT_EQ(b.robust, robust_at.at(b.stamp.nanoseconds()))
        << "the tracker's flags, keyframe " << k;
    differing += a.robust != b.robust;
  }
  EXPECT_GT(differing, 0) << "the tracker's flags differ from the registration's";
}

// Live frames that pause (no frame for a while): the held keyframe leaves with the flags Flush
// gives it (backward half of the window), but the frames after the pause are tracked as without
// the pause (Flush would start a new sequence there, as at a mode switch).
TEST(MapFeatureTrackingTest, PauseReleasesTheHeldKeyframeAndTheSequenceGoesOn) {
  FrontendRun run;
  run.options.map_features.source = MapFeatureSource::kTracker;
  KeyframePtr made;
  const std::unique_ptr<RgbdFrontend> frontend = run.Frontend(&made);
  MapFeatureTracking uninterrupted(run.options.map_features);
  MapFeatureTracking paused(run.options.map_features);
  MapFeatureTracking flushed(run.options.map_features);
  std::optional<FrontendKeyframe> at_pause, flushed_at_pause;
  std::vector<FrontendKeyframe> after_uninterrupted, after_paused, after_flushed;
  for (size_t i = 0; i < std::min(run.sim.size(), kFrames); ++i) {
    ASSERT_TRUE(run.Process(i, frontend.get(), &made));
    Time stamp;
    const FeatureSet* features = frontend->last_frame_features(&stamp);
    ASSERT_NE(features, nullptr);
    const std::optional<FrontendKeyframe> a = uninterrupted.AfterFrame(stamp, features, made);
    const std::optional<FrontendKeyframe> b = paused.AfterFrame(stamp, features, made);
    const std::optional<FrontendKeyframe> c = flushed.AfterFrame(stamp, features, made);
    // The keyframes made after the pause (the uninterrupted run releases the paused one now).
    if (at_pause && a && a->stamp > at_pause->stamp) after_uninterrupted.push_back(*a);
    if (at_pause && b) after_paused.push_back(*b);
    if (at_pause && c) after_flushed.push_back(*c);
    if (!at_pause && i >= 4 && paused.holding()) {  // the frames pause after this one
      at_pause = paused.ReleaseHeld();
      ASSERT_TRUE(at_pause.has_value());
      EXPECT_EQ(at_pause->stamp, stamp);
      EXPECT_FALSE(paused.holding());
      EXPECT_FALSE(paused.ReleaseHeld().has_value()) << "released once";
      flushed_at_pause = flushed.Flush();
      ASSERT_TRUE(flushed_at_pause.has_value());
    }
  }
  ASSERT_TRUE(at_pause.has_value()) << "no keyframe was made after the fifth frame";
  EXPECT_EQ(at_pause->robust, flushed_at_pause->robust) << "the backward half, as Flush";
  EXPECT_EQ(at_pause->features.size(), flushed_at_pause->features.size());
  ASSERT_GE(after_paused.size(), 2u) << "keyframes after the pause";
  ASSERT_EQ(after_paused.size(), after_uninterrupted.size());
  for (size_t k = 0; k < after_paused.size(); ++k) {
    EXPECT_EQ(after_paused[k].stamp, after_uninterrupted[k].stamp);
    EXPECT_EQ(after_paused[k].robust, after_uninterrupted[k].robust)
        << "keyframe " << k << " after the pause: tracked as without it";
  }
  // A restarted sequence (Flush) would have changed them: the check above can fail.
  ASSERT_EQ(after_flushed.size(), after_uninterrupted.size());
  int changed_by_restart = 0;
  for (size_t k = 0; k < after_flushed.size(); ++k) {
    changed_by_restart += after_flushed[k].robust != after_uninterrupted[k].robust;
  }
  EXPECT_GT(changed_by_restart, 0);
}

}  // namespace
}  // namespace icgm
