// The hybrid map with loop closure on a REAL crowd: the Bonn RGB-D Dynamic "crowd" excerpt in
// ../shared (hand-held Xtion, people walking 0.5-2 m from the camera, no wheels), with the
// hand-held crowd profiles config/odometry_handheld_crowd.yaml and config/map_handheld_crowd.yaml
// (README: Hand-held camera in a real crowd). Skipped, loudly, without the data.
#include <filesystem>
#include <memory>
#include <string>

#include <gtest/gtest.h>

#include "core/common/option_reader.h"
#include "core/dataset/camera_options.h"
#include "core/eval/trajectory_evaluation.h"
#include "core/slam/slam_options.h"
#include "core/slam/slam_runner.h"
#include "core/slam/slam_system.h"

namespace icgm {
namespace {

const std::string kBonnDir = std::string(ICGM_SHARED_DATA_DIR) + "/bonn_crowd_excerpt";
const std::string kConfigDir = std::string(ICGM_SOURCE_DIR) + "/config/";

// The hand-held crowd's odometry profile with the map options of `map_yaml` (under config/).
SlamOptions HandheldCrowdOptions(const std::string& map_yaml) {
  SlamOptions options;
  const OptionReader icgm = OptionReader::FromFile(kConfigDir + "icgm.yaml");
  ReadFrontendOptions(OptionReader::FromFile(kConfigDir + "odometry_handheld_crowd.yaml"), icgm,
                      &options.frontend);
  ReadOptions(icgm, &options.map_features.tracker);
  ReadMapSlamOptions(OptionReader::FromFile(kConfigDir + map_yaml), &options);
  return options;
}

double AteRmse(const Trajectory& groundtruth, const Trajectory& estimate) {
  TrajectoryEvaluation eval;
  const Status s = EvaluateTrajectory(groundtruth, estimate, TrajectoryEvalOptions(), &eval);
  EXPECT_TRUE(s.ok()) << s.reason();
  EXPECT_GT(eval.num_associated(), estimate.size() * 9 / 10);
  return s.ok() ? eval.ate.rmse : 1e9;
}

TEST(BonnCrowdMapTest, HandheldCrowdMapProfileOnTheRealBonnCrowd) {
  if (!std::filesystem::exists(kBonnDir + "/rgb.txt")) {
    GTEST_SKIP() << "SKIPPED: real Bonn crowd excerpt not found in " << kBonnDir;
  }
  const auto dataset = std::make_shared<TumDataset>(
      TumDataset::Open(kBonnDir, LoadCameraIntrinsics(kConfigDir + "camera/bonn_xtion.yaml")));
  ASSERT_GE(dataset->size(), 290u);
  ASSERT_TRUE(dataset->has_groundtruth());
  const SlamOptions options = HandheldCrowdOptions("map_handheld_crowd.yaml");
  ASSERT_EQ(options.map.loop_closure.correction, LoopCorrection::kPoseGraph);
  SlamSystem system(options, dataset->intrinsics());
  const SlamRunReport report = RunSlam(&system, TumFrameSource(dataset), SlamRunOptions());
  ASSERT_TRUE(report.input_error.empty()) << report.input_error;
  ASSERT_EQ(report.frames, dataset->size());

  // Loop links reach back to the session's first keyframes, seen before the walkers came, also
  // from the keyframes of the first seconds (within exclude_recent_keyframes of them).
  const LoopClosureOptions& loop = options.map.loop_closure;
  int start_links = 0, early_start_links = 0, loop_links = 0;
  for (const Link& link : system.map().links()) {
    if (link.type != LinkType::kLoopClosure) continue;
    ++loop_links;
    if (link.from_id >= loop.start_candidates) continue;
    ++start_links;
    if (link.to_id - 1 - link.from_id < loop.exclude_recent_keyframes) ++early_start_links;
  }
  const double map_ate = AteRmse(dataset->groundtruth(), system.MapTrajectory());
  const double frontend_ate = AteRmse(dataset->groundtruth(), system.OdomTrajectory());
  std::printf(
      "Bonn crowd excerpt, hand-held crowd profiles (RANSAC seed %u): map ATE %.4f m, "
      "front end %.4f m; %d loop links, %d to the first keyframes (%d of the first seconds)\n",
      static_cast<unsigned>(options.frontend.registration.rng_seed), map_ate, frontend_ate,
      loop_links, start_links, early_start_links);
  EXPECT_GE(start_links, 3);
  EXPECT_GE(early_start_links, 3);
  EXPECT_LT(map_ate, frontend_ate);
  EXPECT_LE(map_ate, 0.033);
}

}  // namespace
}  // namespace icgm
