// The shipped scenarios deliver what later tests rely on: views rich in corners with valid
// depth all along the route, and a crowd that covers a large part of the image at times.
#include <gtest/gtest.h>

#include <algorithm>
#include <string>
#include <vector>

#include <opencv2/features2d.hpp>
#include <opencv2/imgproc.hpp>

#include "core/sim/simulator.h"

namespace icgm::sim {
namespace {

SimOptions Scenario(const std::string& name) {
  return LoadSimOptions(std::string(ICGM_SOURCE_DIR) + "/config/sim/" + name + ".yaml");
}

// FAST corners on pixels with valid depth: features usable for RGB-D registration.
int CornersWithDepth(const SimFrame& f) {
  cv::Mat grey;
  cv::cvtColor(f.bgr, grey, cv::COLOR_BGR2GRAY);
  std::vector<cv::KeyPoint> corners;
  cv::FAST(grey, corners, 20, true);
  int n = 0;
  for (const cv::KeyPoint& k : corners) {
    const float z = f.depth_m.at<float>(cvRound(k.pt.y), cvRound(k.pt.x));
    if (z == z) ++n;
  }
  return n;
}

TEST(ScenarioTest, TwoLapRouteViewsAreTexturedAndWithinDepthRange) {
  const Simulator sim(Scenario("two_lap_loop"));
  RenderFlags static_only;
  static_only.pedestrians = false;
  for (size_t i = 0; i < sim.size(); i += 57) {
    const SimFrame f = sim.Render(i, static_only);
    const double valid = cv::countNonZero(f.depth_m == f.depth_m) / double(f.depth_m.total());
    EXPECT_GT(valid, 0.7) << "frame " << i;
    EXPECT_GT(CornersWithDepth(f), 500) << "frame " << i;
  }
}

TEST(ScenarioTest, CrowdedScenarioCoversMuchOfTheViewAtTimes) {
  const Simulator sim(Scenario("crowded"));
  ASSERT_GE(sim.crowd().num_pedestrians(), 30u);
  double max_coverage = 0.0, sum = 0.0;
  int frames = 0;
  for (size_t i = 0; i < sim.size(); i += 6) {
    const SimFrame f = sim.Render(i);
    const double coverage = cv::countNonZero(f.dynamic_mask) / double(f.dynamic_mask.total());
    max_coverage = std::max(max_coverage, coverage);
    sum += coverage;
    ++frames;
  }
  EXPECT_GT(max_coverage, 0.3);
  EXPECT_LT(max_coverage, 0.8);  // the robot still sees its surroundings
  EXPECT_GT(sum / frames, 0.05);
}

TEST(ScenarioTest, StaticScenarioHasNoPedestrians) {
  const Simulator sim(Scenario("static_short"));
  EXPECT_EQ(sim.crowd().num_pedestrians(), 0u);
  EXPECT_EQ(cv::countNonZero(sim.Render(sim.size() / 2).dynamic_mask), 0);
}

}  // namespace
}  // namespace icgm::sim
