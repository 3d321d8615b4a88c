// The residual trend vote (residual_trend.h): on hand-made residual tracks, and on a rendered
// hand-held crowd, where the simulator's masks tell whether the voted-out points are walkers.
#include "core/odometry/residual_trend.h"

#include <algorithm>
#include <cstdio>
#include <map>
#include <random>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "core/common/option_reader.h"
#include "core/odometry/rgbd_frontend.h"
#include "core/sim/sim_options.h"
#include "core/sim/simulator.h"

namespace icgm {
namespace {

ResidualTrendOptions On() {
  ResidualTrendOptions o;
  o.frames = 4;
  return o;
}

// 60 room points (residual noise 0.5 px) spread over the image and a walker of 15 points around
// (400, 200) whose residual grows by `walker_px_per_frame` along x each frame.
std::vector<TrendObservation> Frame(int frame, double walker_px_per_frame, std::mt19937* rng,
                                    int room_points = 60) {
  std::normal_distribution<double> noise(0.0, 0.5);
  std::vector<TrendObservation> out;
  for (int k = 0; k < room_points; ++k) {
    TrendObservation o;
    o.reference_keypoint = k;
    o.reference_px = cv::Point2f(20.0f + 71.0f * (k % 9), 20.0f + 67.0f * (k / 9));
    o.residual_px = {noise(*rng), noise(*rng)};
    out.push_back(o);
  }
  for (int k = 0; k < 15; ++k) {
    TrendObservation o;
    o.reference_keypoint = 100 + k;
    o.reference_px = cv::Point2f(380.0f + 8.0f * (k % 5), 180.0f + 12.0f * (k / 5));
    o.residual_px = {walker_px_per_frame * frame + noise(*rng), noise(*rng)};
    out.push_back(o);
  }
  return out;
}

TEST(ResidualTrendTest, VotesOutTheSteadilyDriftingBlobAndNoRoomPoint) {
  ResidualTrend trend(On());
  trend.Reset(7, 200);
  std::mt19937 rng(3);
  std::vector<int> voted;
  for (int f = 1; f <= 6; ++f) {
    const std::vector<int> now = trend.Observe(Frame(f, 1.5, &rng));
    voted.insert(voted.end(), now.begin(), now.end());
  }
  EXPECT_EQ(voted.size(), 15u);
  for (const int k : voted) EXPECT_GE(k, 100) << "room point " << k << " voted out";
  EXPECT_TRUE(trend.voted(104));
  EXPECT_FALSE(trend.voted(4));
  // Voted once: later frames do not vote the same points again.
  EXPECT_TRUE(trend.Observe(Frame(7, 1.5, &rng)).empty());
}

TEST(ResidualTrendTest, NoVoteWithoutSteadyGrowthOrNeighbours) {
  std::mt19937 rng(5);
  // A walker standing still for the camera: residuals at noise level.
  ResidualTrend still(On());
  still.Reset(0, 200);
  for (int f = 1; f <= 8; ++f) EXPECT_TRUE(still.Observe(Frame(f, 0.0, &rng)).empty());
  // A lone drifting point has no neighbour drifting alike.
  ResidualTrendOptions options = On();
  ResidualTrend lone(options);
  lone.Reset(0, 200);
  for (int f = 1; f <= 8; ++f) {
    std::vector<TrendObservation> obs = Frame(f, 0.0, &rng);
    obs[10].residual_px = {2.0 * f, 0.0};
    EXPECT_TRUE(lone.Observe(obs).empty());
  }
}

TEST(ResidualTrendTest, NoVoteWhenMostOfTheFrameDrifts) {
  // Only 5 room points: the drifting walker is most of the frame, so the motion followed the
  // walkers and nothing is voted.
  ResidualTrend trend(On());
  trend.Reset(0, 200);
  std::mt19937 rng(9);
  for (int f = 1; f <= 8; ++f) EXPECT_TRUE(trend.Observe(Frame(f, 1.5, &rng, 5)).empty());
}

TEST(ResidualTrendTest, StartsOverForANewReference) {
  ResidualTrend trend(On());
  trend.Reset(3, 200);
  std::mt19937 rng(11);
  for (int f = 1; f <= 6; ++f) trend.Observe(Frame(f, 1.5, &rng));
  EXPECT_TRUE(trend.voted(100));
  EXPECT_TRUE(trend.tracking(3));
  trend.Reset(4, 200);
  EXPECT_FALSE(trend.tracking(3));
  EXPECT_FALSE(trend.voted(100));
  EXPECT_EQ(trend.frames_observed(), 0u);
}

FrontendOptions HandheldProfile() {
  FrontendOptions o;
  ReadFrontendOptions(OptionReader::FromFile(std::string(ICGM_SOURCE_DIR) +
                                             "/config/odometry_handheld_crowd.yaml"),
                      OptionReader::FromFile(std::string(ICGM_SOURCE_DIR) + "/config/icgm.yaml"),
                      &o);
  return o;
}

TEST(ResidualTrendTest, VotedOutReferencePointsAreOnWalkersInARenderedHandheldCrowd) {
  // config/sim/handheld_crowd.yaml, scenario seed 1, frames 140-199: a walker crosses near the
  // hand-held camera while frames stay on one keyframe. The simulator's masks tell whether each
  // voted-out reference keypoint lies on a walker in its reference frame.
  sim::SimOptions scenario =
      sim::LoadSimOptions(std::string(ICGM_SOURCE_DIR) + "/config/sim/handheld_crowd.yaml");
  scenario.seed = 1;
  const sim::Simulator sim(scenario);
  FrontendOptions options = HandheldProfile();
  ASSERT_FALSE(options.residual_trend.on()) << "shipped off";
  options.residual_trend.frames = 8;
  RgbdFrontend frontend(options, sim.intrinsics());
  std::map<size_t, cv::Mat> masks;  // by the front end's frame index
  size_t voted = 0, on_walkers = 0;
  constexpr size_t kFirst = 140, kFrames = 60;
  for (size_t i = kFirst; i < kFirst + kFrames; ++i) {
    const sim::SimFrame f = sim.Render(i);
    const FrontendFrameResult r = frontend.ProcessFrame(f.stamp, f.bgr, f.depth_m);
    masks[r.frame_index] = f.dynamic_mask;
    if (r.trend_voted_reference_px.empty()) continue;
    ASSERT_TRUE(r.reference_index.has_value());
    const cv::Mat& mask = masks.at(*r.reference_index);
    for (const cv::Point2f& p : r.trend_voted_reference_px) {
      ++voted;
      on_walkers += mask.at<uint8_t>(std::clamp(cvRound(p.y), 0, mask.rows - 1),
                                     std::clamp(cvRound(p.x), 0, mask.cols - 1)) != 0;
    }
  }
  std::printf("residual trend, handheld crowd seed 1, frames %zu-%zu: %zu reference keypoints "
              "voted out, %zu on walkers\n",
              kFirst, kFirst + kFrames - 1, voted, on_walkers);
  EXPECT_GE(voted, 10u);
  EXPECT_GE(on_walkers, 0.8 * voted);
}

}  // namespace
}  // namespace icgm
