// Every shipped scenario loads, builds a simulator and has the frame count its name promises;
// bad values and unknown keys are rejected with the key's path.
#include "core/sim/sim_options.h"

#include <gtest/gtest.h>

#include <filesystem>
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

}  // namespace
}  // namespace icgm::sim
