// Localization mode of SlamSystem: a map of the first lap of the small loop, then a robot that
// starts somewhere on the second lap with its odometry restarted (an unknown T_map_odom) must
// relocalize by place recognition within a few frames, at the true pose, without writing the
// learned map.
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <iterator>
#include <memory>
#include <string>
#include <vector>

#include "core/sim/sim_options.h"
#include "core/sim/simulator.h"
#include "core/slam/slam_system.h"

namespace icgm {
namespace {

namespace fs = std::filesystem;

std::string ReadBytes(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
}

class LocalizationTest : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    sim_ = std::make_unique<sim::Simulator>(
        sim::LoadSimOptions(std::string(ICGM_SOURCE_DIR) + "/config/sim/small_loop.yaml"));
    options_ = LoadSlamOptions(std::string(ICGM_SOURCE_DIR) + "/config");
    options_.frontend.fusion.base_to_camera = sim_->T_base_camera();
    dir_ = fs::temp_directory_path() / ("icgm_localization_" + std::to_string(::getpid()));
    fs::create_directories(dir_);
    map_path_ = (dir_ / "lap.db").string();
    // Mapping: the first lap (the scenario drives two).
    lap_frames_ = sim_->size() / 2;
    SlamSystem mapping(options_, sim_->intrinsics());
    for (size_t i = 0; i < lap_frames_; ++i) {
      mapping.AddWheelOdometry(sim_->stamp(i), sim_->odometry(i).T_odom_base);
      const sim::SimFrame f = sim_->Render(i);
      mapping.ProcessFrame(f.stamp, f.bgr, f.depth_m);
    }
    learned_keyframes_ = mapping.map().size();
    ASSERT_TRUE(mapping.Save(map_path_).ok());
    // The map frame in the simulator's world, anchored at the first frame.
    world_from_map_ = sim_->T_world_camera(0) * mapping.MapTrajectory().front().pose.inverse();
  }
  static void TearDownTestSuite() {
    fs::remove_all(dir_);
    sim_.reset();
  }

  // Runs `system` (a loaded map, localization mode) from frame `first` with the odometry
  // restarted at an arbitrary pose. Returns the frame count until the first fix (-1: none
  // within max_frames) and leaves the pose error of the last frame in *error_m.
  int RunFrom(SlamSystem* system, size_t first, size_t max_frames, double* error_m,
              size_t extra_frames = 8) {
    const Pose3 offset = MakePose({3.0, -2.0, 0.0}, Quat(Eigen::AngleAxisd(1.2, Vec3::UnitZ())));
    const Pose3 odom0_inv = sim_->odometry(first).T_odom_base.inverse();
    int fixed_after = -1;
    size_t until = first + max_frames;
    for (size_t i = first; i < until && i < sim_->size(); ++i) {
      system->AddWheelOdometry(sim_->stamp(i), offset * odom0_inv * sim_->odometry(i).T_odom_base);
      const sim::SimFrame f = sim_->Render(i);
      const SlamFrameResult r = system->ProcessFrame(f.stamp, f.bgr, f.depth_m);
      std::string written;  // as the map-building nodelet does after every keyframe
      EXPECT_TRUE(system->Autosave(r, &written).ok());
      if (!written.empty()) written_.push_back(written);
      if (fixed_after < 0 && system->localized()) {
        fixed_after = static_cast<int>(i - first + 1);
        until = i + 1 + extra_frames;  // keep tracking a little
      }
      const Pose3 truth = world_from_map_.inverse() * sim_->T_world_camera(i);
      *error_m = TranslationNorm(Between(truth, r.map_camera));
    }
    return fixed_after;
  }

  std::vector<std::string> written_;  // autosaved files
  static std::unique_ptr<sim::Simulator> sim_;
  static SlamOptions options_;
  static fs::path dir_;
  static std::string map_path_;
  static size_t lap_frames_;
  static int learned_keyframes_;
  static Pose3 world_from_map_;
};

std::unique_ptr<sim::Simulator> LocalizationTest::sim_;
SlamOptions LocalizationTest::options_;
fs::path LocalizationTest::dir_;
std::string LocalizationTest::map_path_;
size_t LocalizationTest::lap_frames_ = 0;
int LocalizationTest::learned_keyframes_ = 0;
Pose3 LocalizationTest::world_from_map_ = Pose3::Identity();

TEST_F(LocalizationTest, RelocalizesGloballyWithoutWritingTheMap) {
  ASSERT_GE(learned_keyframes_, 20);
  const std::string before = ReadBytes(map_path_);
  SlamSystem system(options_, sim_->intrinsics());
  ASSERT_TRUE(system.Load(map_path_, false).ok());
  ASSERT_TRUE(system.SetMode("localization").ok());
  const std::string localization_path = (dir_ / "lap_localization.db").string();
  system.SetSavePolicy({map_path_, localization_path, 1});
  EXPECT_FALSE(system.localized());
  double error_m = 1e9;
  // Two places of the second lap, a third and two thirds of the way round.
  const int fixed_after = RunFrom(&system, lap_frames_ + lap_frames_ / 3, 20, &error_m);
  ASSERT_GT(fixed_after, 0) << "not relocalized within 20 frames";
  std::printf("relocalized after %d frames; pose error %.3f m %zu fixes\n", fixed_after, error_m,
              system.relocalizations());
  EXPECT_LE(fixed_after, 12);
  EXPECT_LT(error_m, 0.15);
  // Nothing written into the learned map, in memory or on disk; autosave has nothing to write.
  EXPECT_EQ(system.map().size(), learned_keyframes_);
  EXPECT_EQ(ReadBytes(map_path_), before);
  EXPECT_FALSE(fs::exists(localization_path));
  EXPECT_TRUE(written_.empty());
  const Status refused = system.SaveMap(map_path_, true);
  EXPECT_FALSE(refused.ok());
  EXPECT_NE(refused.reason().find("never writes the learned map"), std::string::npos);
  EXPECT_EQ(ReadBytes(map_path_), before);
}

TEST_F(LocalizationTest, KeptKeyframesGoToASeparateSessionAndFile) {
  SlamOptions options = options_;
  options.localization.keyframes = LocalizationKeyframes::kSession;
  SlamSystem system(options, sim_->intrinsics());
  ASSERT_TRUE(system.Load(map_path_, false).ok());
  const HybridMap learned = system.map();
  system.SetMode(MapMode::kLocalization);
  const std::string localization_path = (dir_ / "kept_localization.db").string();
  system.SetSavePolicy({map_path_, localization_path, 1});
  const std::string before = ReadBytes(map_path_);
  double error_m = 1e9;
  const int fixed_after = RunFrom(&system, lap_frames_ + 2 * lap_frames_ / 3, 20, &error_m);
  ASSERT_GT(fixed_after, 0);
  EXPECT_LT(error_m, 0.15);
  ASSERT_GT(system.map().size(), learned.size());
  for (int id = 0; id < learned.size(); ++id) {
    EXPECT_TRUE(system.map().keyframe(id).global_pose.isApprox(learned.keyframe(id).global_pose,
                                                               1e-12))
        << "learned keyframe " << id << " moved";
  }
  for (int id = learned.size(); id < system.map().size(); ++id) {
    EXPECT_NE(system.map().keyframe(id).session_id, learned.keyframe(0).session_id);
  }
  EXPECT_EQ(ReadBytes(map_path_), before);
  ASSERT_FALSE(written_.empty()) << "no autosave";
  for (const std::string& w : written_) EXPECT_EQ(w, localization_path);
  EXPECT_TRUE(fs::exists(localization_path));
}

TEST_F(LocalizationTest, InitialPoseGivesAFixAndUnknownModesAreErrors) {
  SlamSystem system(options_, sim_->intrinsics());
  ASSERT_TRUE(system.Load(map_path_, false).ok());
  const Status bad = system.SetMode("navigation");
  EXPECT_FALSE(bad.ok());
  EXPECT_EQ(system.mode(), MapMode::kMapping);
  ASSERT_TRUE(system.SetMode("localization").ok());
  // The true pose of the first frame, as rviz's /initialpose would give it (the odometry of a
  // fresh front end starts at the wheel pose, here the identity).
  const size_t first = lap_frames_ + lap_frames_ / 2;
  const Pose3 map_camera = world_from_map_.inverse() * sim_->T_world_camera(first);
  const Pose3 odom_camera = sim_->T_base_camera();
  system.SetInitialPose(map_camera, odom_camera);
  EXPECT_TRUE(system.localized());
  EXPECT_TRUE(system.MapFromOdom().isApprox(map_camera * odom_camera.inverse(), 1e-12));
  double error_m = 1e9;
  for (size_t i = first; i < first + 12; ++i) {
    system.AddWheelOdometry(sim_->stamp(i),
                            sim_->odometry(first).T_odom_base.inverse() *
                                sim_->odometry(i).T_odom_base);
    const sim::SimFrame f = sim_->Render(i);
    const SlamFrameResult r = system.ProcessFrame(f.stamp, f.bgr, f.depth_m);
    error_m = TranslationNorm(
        Between(world_from_map_.inverse() * sim_->T_world_camera(i), r.map_camera));
  }
  EXPECT_LT(error_m, 0.15);
  EXPECT_EQ(system.map().size(), learned_keyframes_);
}

}  // namespace
}  // namespace icgm
