// LiveMap: keyframes handed over from a separate front end (as the registration nodelet hands
// them to the map builder nodelet) build the map SlamSystem::ProcessFrame builds offline, and
// requests made before the camera is known apply when it is.
#include "core/slam/live_map.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include "core/sim/sim_options.h"
#include "core/sim/simulator.h"

namespace icgm {
namespace {

namespace fs = std::filesystem;

constexpr size_t kFrames = 60;

class LiveMapTest : public ::testing::Test {
 protected:
  void SetUp() override {
    sim_ = std::make_unique<sim::Simulator>(
        sim::LoadSimOptions(std::string(ICGM_SOURCE_DIR) + "/config/sim/small_loop.yaml"));
    options_ = LoadSlamOptions(std::string(ICGM_SOURCE_DIR) + "/config");
    options_.frontend.fusion.base_to_camera = sim_->T_base_camera();
    dir_ = fs::temp_directory_path() /
           ("icgm_live_map_test_" + std::to_string(::getpid()) + "_" +
            ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  std::string Path(const std::string& name) const { return (dir_ / name).string(); }

  std::unique_ptr<sim::Simulator> sim_;
  SlamOptions options_;
  fs::path dir_;
};

TEST_F(LiveMapTest, HandedOverKeyframesBuildTheOfflineMap) {
  SlamSystem offline(options_, sim_->intrinsics());
  RgbdFrontend frontend(options_.frontend, sim_->intrinsics());
  std::vector<KeyframePtr> keyframes;
  frontend.SetKeyframeCallback([&](const KeyframePtr& k) { keyframes.push_back(k); });
  for (size_t i = 0; i < kFrames; ++i) {
    offline.AddWheelOdometry(sim_->stamp(i), sim_->odometry(i).T_odom_base);
    frontend.AddWheelOdometry(sim_->stamp(i), sim_->odometry(i).T_odom_base);
    const sim::SimFrame f = sim_->Render(i);
    offline.ProcessFrame(f.stamp, f.bgr, f.depth_m);
    frontend.ProcessFrame(f.stamp, f.bgr, f.depth_m);
  }
  LiveMap live(options_, LiveMapOptions());
  std::string loaded;
  ASSERT_TRUE(live.Start(sim_->intrinsics(), &loaded).ok());
  EXPECT_TRUE(loaded.empty());
  for (const KeyframePtr& k : keyframes) {
    const LiveMapUpdate update = live.AddKeyframe(*k);
    EXPECT_TRUE(update.result.map_status.ok()) << update.result.map_status.reason();
    EXPECT_TRUE(update.saved_to.empty());  // no map_path: nothing written
  }
  const HybridMap& a = offline.map();
  const HybridMap& b = live.system()->map();
  EXPECT_GE(a.size(), 3);
  ASSERT_EQ(b.size(), a.size());
  for (int i = 0; i < a.size(); ++i) {
    EXPECT_EQ(b.keyframe(i).stamp, a.keyframe(i).stamp);
    EXPECT_EQ(b.keyframe(i).keypoints.size(), a.keyframe(i).keypoints.size());
    EXPECT_LT((b.keyframe(i).global_pose.matrix() - a.keyframe(i).global_pose.matrix()).norm(),
              1e-9);
  }
  EXPECT_TRUE(live.system()->MapFromOdom().isApprox(offline.MapFromOdom(), 1e-9));
}

TEST_F(LiveMapTest, RequestsBeforeTheCameraApplyAtStart) {
  LiveMapOptions o;
  o.map_path = Path("map.db");
  LiveMap live(options_, o);
  std::string message;
  EXPECT_FALSE(live.SetMode("localisation", &message).ok());
  ASSERT_TRUE(live.SetMode("localization", &message).ok());
  EXPECT_TRUE(live.Save("", &message).reason().find("no map yet") != std::string::npos);
  ASSERT_TRUE(live.Load(Path("missing.db"), false, &message).ok());  // deferred
  EXPECT_FALSE(live.started());
  std::string loaded;
  EXPECT_FALSE(live.Start(sim_->intrinsics(), &loaded).ok());  // the deferred load fails
  ASSERT_TRUE(live.started());
  EXPECT_EQ(live.system()->mode(), MapMode::kLocalization);
  EXPECT_TRUE(live.LocalizingWithoutMap());
  EXPECT_EQ(live.system()->save_policy().localization_path, Path("map_localization.db"));
}

TEST_F(LiveMapTest, ShutdownSaveFollowsTheMode) {
  RgbdFrontend frontend(options_.frontend, sim_->intrinsics());
  std::vector<KeyframePtr> keyframes;
  frontend.SetKeyframeCallback([&](const KeyframePtr& k) { keyframes.push_back(k); });
  for (size_t i = 0; i < 20; ++i) {
    frontend.AddWheelOdometry(sim_->stamp(i), sim_->odometry(i).T_odom_base);
    const sim::SimFrame f = sim_->Render(i);
    frontend.ProcessFrame(f.stamp, f.bgr, f.depth_m);
  }
  ASSERT_FALSE(keyframes.empty());
  LiveMapOptions o;
  o.map_path = Path("map.db");
  o.autosave_every_keyframes = 0;
  LiveMap live(options_, o);
  std::string written;
  EXPECT_TRUE(live.SaveAtShutdown(&written).ok());  // not started: nothing to write
  EXPECT_TRUE(written.empty());
  std::string loaded;
  ASSERT_TRUE(live.Start(sim_->intrinsics(), &loaded).ok());
  for (const KeyframePtr& k : keyframes) live.AddKeyframe(*k);
  ASSERT_TRUE(live.SaveAtShutdown(&written).ok());
  EXPECT_EQ(written, Path("map.db"));
  EXPECT_TRUE(fs::exists(Path("map.db")));
  // Localization that keeps no keyframes changed nothing: no shutdown save.
  options_.localization.keyframes = LocalizationKeyframes::kNone;
  o.load_path = Path("map.db");
  o.mode = MapMode::kLocalization;
  LiveMap localizing(options_, o);
  ASSERT_TRUE(localizing.Start(sim_->intrinsics(), &loaded).ok());
  EXPECT_FALSE(loaded.empty());
  ASSERT_TRUE(localizing.SaveAtShutdown(&written).ok());
  EXPECT_TRUE(written.empty());
  EXPECT_FALSE(fs::exists(Path("map_localization.db")));
}

TEST(LocalizationMapPathFor, NamesTheSecondFile) {
  EXPECT_EQ(LocalizationMapPathFor("/maps/lab.db"), "/maps/lab_localization.db");
  EXPECT_EQ(LocalizationMapPathFor("/maps/lab"), "/maps/lab_localization.db");
  EXPECT_EQ(LocalizationMapPathFor(""), "");
}

}  // namespace
}  // namespace icgm
