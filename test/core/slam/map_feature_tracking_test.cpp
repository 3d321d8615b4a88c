#include "core/slam/map_feature_tracking.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <map>
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
  sim::Simulator sim;
  SlamOptions options;
};

TEST(MapFeatureTrackingTest, ReferenceKeyframeSourcePassesEachKeyframeAtOnce) {
  FrontendRun run;
  run.options.map_features.source = MapFeatureSource::kReferenceKeyframe;
  RgbdFrontend frontend(run.options.frontend, run.sim.intrinsics());
  KeyframePtr made;
  frontend.SetKeyframeCallback([&](const KeyframePtr& k) { made = k; });
  MapFeatureTracking tracking(run.options.map_features);
  EXPECT_FALSE(tracking.holds_keyframes());
  int released = 0;
  for (size_t i = 0; i < std::min(run.sim.size(), kFrames); ++i) {
    ASSERT_TRUE(frontend.AddWheelOdometry(run.sim.stamp(i), run.sim.odometry(i).T_odom_base));
    const sim::SimFrame f = run.sim.Render(i);
    made.reset();
    frontend.ProcessFrame(f.stamp, f.bgr, f.depth_m);
    const KeyframePtr expected = made;
    const std::optional<FrontendKeyframe> k = tracking.AfterFrame(frontend, std::move(made));
    ASSERT_EQ(k.has_value(), expected != nullptr) << "frame " << i;
    if (!k) continue;
    ++released;
    EXPECT_EQ(k->stamp, f.stamp);
    EXPECT_EQ(k->robust, expected->robust) << "the registration's flags";
  }
  EXPECT_GE(released, 3);
  EXPECT_FALSE(tracking.Flush().has_value());
}

TEST(MapFeatureTrackingTest, TrackerSourceReleasesEachKeyframeAfterItsNextFrame) {
  FrontendRun run;
  run.options.map_features.source = MapFeatureSource::kTracker;
  RgbdFrontend frontend(run.options.frontend, run.sim.intrinsics());
  KeyframePtr made;
  frontend.SetKeyframeCallback([&](const KeyframePtr& k) { made = k; });
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
    ASSERT_TRUE(frontend.AddWheelOdometry(run.sim.stamp(i), run.sim.odometry(i).T_odom_base));
    const sim::SimFrame f = run.sim.Render(i);
    stamps.push_back(f.stamp);
    made.reset();
    frontend.ProcessFrame(f.stamp, f.bgr, f.depth_m);
    Time stamp;
    const FeatureSet* features = frontend.last_frame_features(&stamp);
    ASSERT_NE(features, nullptr);
    keep(reference.AddFeatures(stamp, *features));
    if (made) made_all.push_back(*made);
    const bool had_held = tracking.holding();
    if (std::optional<FrontendKeyframe> k = tracking.AfterFrame(frontend, std::move(made))) {
      ASSERT_TRUE(had_held);
      ASSERT_GE(i, 1u);
      EXPECT_EQ(k->stamp, stamps[i - 1]) << "released with the frame after its own";
      released.push_back(*k);
    }
    // The same frame again (a frame the front end dropped): nothing is fed twice.
    EXPECT_FALSE(tracking.AfterFrame(frontend, nullptr).has_value());
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

}  // namespace
}  // namespace icgm
