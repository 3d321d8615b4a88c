// Every shipped scenario loads, builds a simulator and has the frame count its name promises;
// bad values and unknown keys are rejected with the key's path.
#include "core/sim/sim_options.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <iostream>
#include <map>
#include <string>

#include "core/common/status.h"
#include "core/sim/simulator.h"

namespace icgm::sim {
namespace {

namespace fs = std::filesystem;

TEST(SimOptionsTest, EveryShippedScenarioLoadsAndBuilds) {
  const fs::path dir = fs::path(ICGM_SOURCE_DIR) / "config" / "sim";
  ASSERT_TRUE(fs::is_directory(dir)) << dir;
  std::map<std::string, size_t> frames;
  for (const auto& entry : fs::directory_iterator(dir)) {
    if (entry.path().extension() != ".yaml") continue;
    SCOPED_TRACE(entry.path().string());
    SimOptions options;
    ASSERT_NO_THROW(options = LoadSimOptions(entry.path().string()));
    // A scenario replaying a recorded camera path needs that recording (shared data).
    const std::string& recorded = options.handheld.recorded_trajectory;
    if (!recorded.empty() && !fs::exists(recorded)) {
      std::cout << "SKIPPED: " << entry.path().filename().string() << " replays " << recorded
                << ", which is not there; its scene is not built\n";
      continue;
    }
    const Simulator sim(options);
    frames[entry.path().stem().string()] = sim.size();
  }
  ASSERT_EQ(frames.count("static_short"), 1u);
  ASSERT_EQ(frames.count("crowded"), 1u);
  ASSERT_EQ(frames.count("two_lap_loop"), 1u);
  EXPECT_NEAR(static_cast<double>(frames["static_short"]), 150.0, 30.0);
  EXPECT_NEAR(static_cast<double>(frames["crowded"]), 300.0, 50.0);
  EXPECT_GE(frames["two_lap_loop"], 1200u);
  EXPECT_LE(frames["two_lap_loop"], 1600u);
  ASSERT_EQ(frames.count("handheld_crowd"), 1u);
  EXPECT_EQ(frames["handheld_crowd"], 300u);  // 10 s at 30 Hz
}

TEST(SimOptionsTest, ReadsNestedValues) {
  const OptionReader reader = OptionReader::FromString(R"(
seed: 5
num_frames: 42
camera: {fx_px: 500.0, width_px: 320, height_px: 240}
crowd: {num_pedestrians: 12, speed_mps: 0.9}
odometry: {scale_error: -0.03}
)");
  SimOptions o;
  ReadOptions(reader, &o);
  EXPECT_EQ(o.seed, 5);
  EXPECT_EQ(o.num_frames, 42);
  EXPECT_DOUBLE_EQ(o.intrinsics.fx_px, 500.0);
  EXPECT_EQ(o.intrinsics.width_px, 320);
  EXPECT_EQ(o.crowd.num_pedestrians, 12);
  EXPECT_DOUBLE_EQ(o.crowd.speed_mps, 0.9);
  EXPECT_DOUBLE_EQ(o.odometry.scale_error, -0.03);
  EXPECT_DOUBLE_EQ(o.room.width_m, 20.0);  // untouched default
}

TEST(SimOptionsTest, RejectsOutOfRangeValueWithKeyPath) {
  const OptionReader reader = OptionReader::FromString("crowd: {speed_mps: 9.0}");
  SimOptions o;
  try {
    ReadOptions(reader, &o);
    FAIL() << "expected LoadError";
  } catch (const LoadError& e) {
    EXPECT_NE(std::string(e.what()).find("crowd.speed_mps"), std::string::npos) << e.what();
  }
}

TEST(SimOptionsTest, RejectsUnknownKey) {
  SimOptions o;
  EXPECT_THROW(ReadOptions(OptionReader::FromString("room: {widht_m: 10}"), &o), LoadError);
  EXPECT_THROW(ReadOptions(OptionReader::FromString("num_frame: 10"), &o), LoadError);
}

TEST(SimOptionsTest, RejectsRouteThatDoesNotFitTheRoom) {
  SimOptions o;
  EXPECT_THROW(
      ReadOptions(
          OptionReader::FromString("room: {width_m: 8, length_m: 8}\nroute: {inset_m: 3.0}"), &o),
      LoadError);
}

TEST(SimOptionsTest, HandheldCameraNeedsNoRouteButMustStartInsideTheRoom) {
  SimOptions o;
  // A room too small for the default route is fine without one.
  ReadOptions(OptionReader::FromString("camera_motion: handheld\n"
                                       "room: {width_m: 6, length_m: 5}\n"
                                       "handheld: {x_m: 3, y_m: 1, height_m: 1.5}\n"
                                       "crowd: {non_yielding_fraction: 1.0}"),
              &o);
  EXPECT_TRUE(o.handheld_camera());
  EXPECT_DOUBLE_EQ(o.handheld.height_m, 1.5);
  EXPECT_DOUBLE_EQ(o.crowd.non_yielding_fraction, 1.0);
  EXPECT_THROW(ReadOptions(OptionReader::FromString("camera_motion: handheld\n"
                                                    "room: {width_m: 6, length_m: 5}\n"
                                                    "handheld: {x_m: 7}"),
                           &o),
               LoadError);
  // A walk of 1 m/s for 10 s (301 frames at 30 Hz) along +y from y = 1 m: 11 m.
  const std::string walk =
      "camera_motion: handheld\nnum_frames: 301\nframe_rate_hz: 30\n"
      "handheld: {x_m: 3, y_m: 1, yaw_deg: 90, walk_speed_mps: 1.0}\n";
  EXPECT_NO_THROW(
      ReadOptions(OptionReader::FromString(walk + "room: {width_m: 6, length_m: 12}"), &o));
  EXPECT_THROW(ReadOptions(OptionReader::FromString(walk + "room: {width_m: 6, length_m: 11}"), &o),
               LoadError);
  EXPECT_THROW(ReadOptions(OptionReader::FromString("camera_motion: walking"), &o), LoadError);
  EXPECT_THROW(ReadOptions(OptionReader::FromString("handheld: {drift_sped_mps: 0.1}"), &o),
               LoadError);
}

TEST(SimOptionsTest, NewOptionsDefaultToTheOldBehaviour) {
  const SimOptions o;
  EXPECT_FALSE(o.handheld_camera());
  EXPECT_EQ(o.exposure_s, 0.0);
  EXPECT_EQ(o.crowd.non_yielding_fraction, 0.0);
  EXPECT_EQ(o.room.wall_contrast, 1.0);
  EXPECT_EQ(o.room.floor_contrast, 1.0);
  EXPECT_EQ(o.room.furniture_contrast, 1.0);
  EXPECT_EQ(o.room.num_desks, 0);
  EXPECT_EQ(o.room.num_chairs, 0);
}


TEST(SimOptionsTest, DriveOptionsAndCrowdSeedAreReadStrictly) {
  SimOptions o;
  EXPECT_EQ(o.effective_crowd_seed(), o.seed);  // unset: follows the world seed
  ReadOptions(OptionReader::FromString("seed: 7\ncrowd_seed: 9\n"
                                       "drive: {max_linear_mps: 0.7, robot_radius_m: 0.25}"),
              &o);
  EXPECT_EQ(o.effective_crowd_seed(), 9);
  EXPECT_DOUBLE_EQ(o.drive.max_linear_mps, 0.7);
  EXPECT_DOUBLE_EQ(o.drive.robot_radius_m, 0.25);
  EXPECT_THROW(ReadOptions(OptionReader::FromString("drive: {max_speed: 1}"), &o), LoadError);
  EXPECT_THROW(ReadOptions(OptionReader::FromString("drive: {max_linear_mps: -1}"), &o), LoadError);
  EXPECT_THROW(ReadOptions(OptionReader::FromString("crowd_seed: -2"), &o), LoadError);
}

}  // namespace
}  // namespace icgm::sim
