#include "core/registration/dynamic_region_fill.h"

#include <gtest/gtest.h>

namespace icgm {
namespace {

// A person-like block 1.0-1.2 m away in front of a wall at 3 m, standing on a floor whose
// depth rises with the row; one seed cell on the person's edge.
struct FillScene {
  static constexpr int kStep = 4, kRows = 40, kCols = 60;
  cv::Mat depth = cv::Mat(kRows * kStep, kCols * kStep, CV_32FC1, cv::Scalar(3.0f));
  cv::Mat seeds = cv::Mat::zeros(kRows, kCols, CV_8UC1);
  FillScene() {
    for (int v = 0; v < depth.rows; ++v) {
      for (int u = 0; u < depth.cols; ++u) {
        const int gv = v / kStep, gu = u / kStep;
        if (gv >= 30) depth.at<float>(v, u) = 3.0f - 0.07f * float(gv - 30);  // floor
        if (gv >= 5 && gv < 32 && gu >= 20 && gu < 35) {
          depth.at<float>(v, u) = 1.0f + 0.01f * float(gu - 20);  // the person, sloping
        }
      }
    }
    seeds.at<uint8_t>(15, 20) = 1;
  }
};

TEST(DynamicRegionFillTest, GrowsOverTheWholePersonAndStopsAtTheBackground) {
  const FillScene s;
  const cv::Mat filled = FillConnectedSurface(s.seeds, s.depth, FillScene::kStep,
                                              {0.05, 0.4, 0.3, 6.0});
  // Every cell of the person, no wall cell.
  int person = 0, wall = 0;
  for (int gv = 0; gv < FillScene::kRows; ++gv) {
    for (int gu = 0; gu < FillScene::kCols; ++gu) {
      const bool on_person = gv >= 5 && gv < 32 && gu >= 20 && gu < 35;
      if (on_person) person += filled.at<uint8_t>(gv, gu) == 255;
      if (!on_person && gv < 30) wall += filled.at<uint8_t>(gv, gu) != 0;
    }
  }
  EXPECT_EQ(person, 27 * 15);
  EXPECT_EQ(wall, 0);
  EXPECT_EQ(filled.at<uint8_t>(15, 20), 255);
}

TEST(DynamicRegionFillTest, TheBandAroundTheSeedDepthLimitsTheGrowthAlongASlope) {
  FillScene s;
  // A floor-like ramp continuous with the seed: 2 cm per cell to the right.
  for (int v = 0; v < s.depth.rows; ++v) {
    for (int u = 0; u < s.depth.cols; ++u) s.depth.at<float>(v, u) = 1.0f + 0.02f * float(u / 4);
  }
  const cv::Mat filled =
      FillConnectedSurface(s.seeds, s.depth, FillScene::kStep, {0.05, 0.2, 0.3, 6.0});
  // Seed at column 20 (1.40 m): columns 10..30 lie within 0.2 m.
  EXPECT_EQ(filled.at<uint8_t>(0, 30), 255);
  EXPECT_EQ(filled.at<uint8_t>(39, 10), 255);
  EXPECT_EQ(filled.at<uint8_t>(15, 31), 0);
  EXPECT_EQ(filled.at<uint8_t>(15, 9), 0);
}

TEST(DynamicRegionFillTest, NoStepOrNoDepthLeavesTheSeeds) {
  const FillScene s;
  cv::Mat filled = FillConnectedSurface(s.seeds, s.depth, FillScene::kStep, {0.0, 0.4, 0.3, 6.0});
  EXPECT_EQ(cv::countNonZero(filled), 1);
  filled = FillConnectedSurface(s.seeds, cv::Mat(), FillScene::kStep, {0.05, 0.4, 0.3, 6.0});
  EXPECT_EQ(cv::countNonZero(filled), 1);
  // Holes in the depth (0 m) around the seed stop the growth (the wall is on its left).
  cv::Mat holes = s.depth.clone();
  holes.colRange(21 * FillScene::kStep, 22 * FillScene::kStep).setTo(0.0f);
  holes.rowRange(14 * FillScene::kStep, 15 * FillScene::kStep).setTo(0.0f);
  holes.rowRange(16 * FillScene::kStep, 17 * FillScene::kStep).setTo(0.0f);
  filled = FillConnectedSurface(s.seeds, holes, FillScene::kStep, {0.05, 0.4, 0.3, 6.0});
  EXPECT_EQ(cv::countNonZero(filled), 1);
}

}  // namespace
}  // namespace icgm
