// FramePairer on streams like a Kinect's: colour every 33.3 ms, depth 8 ms later, with dropped
// frames in either stream and depth sometimes arriving before its colour.
#include "core/sensor/frame_pairer.h"

#include <gtest/gtest.h>

namespace icgm {
namespace {

StampedImage Frame(uint64_t us, int tag) {
  StampedImage f;
  f.device_us = us;
  f.image = cv::Mat(1, 1, CV_32SC1, cv::Scalar(tag));
  return f;
}

TEST(FramePairer, PairsEachDepthWithItsColourAndDropsOrphans) {
  FramePairer pairer(0.0167);
  std::vector<std::pair<int, int>> pairs;
  for (int i = 0; i < 30; ++i) {
    const uint64_t t = 1000 + i * 33333;
    std::optional<RgbdPair> p;
    const bool depth_first = i % 4 == 1;
    if (depth_first) {
      p = pairer.AddDepth(Frame(t + 8000, i));
      if (p) pairs.emplace_back(p->color.image.at<int>(0), p->depth.image.at<int>(0));
    }
    if (i != 7) {  // colour 7 lost
      p = pairer.AddColor(Frame(t, i));
      if (p) pairs.emplace_back(p->color.image.at<int>(0), p->depth.image.at<int>(0));
    }
    if (!depth_first && i != 20) {  // depth 20 lost
      p = pairer.AddDepth(Frame(t + 8000, i));
      if (p) pairs.emplace_back(p->color.image.at<int>(0), p->depth.image.at<int>(0));
    }
  }
  for (const auto& [c, d] : pairs) EXPECT_EQ(c, d);
  EXPECT_EQ(pairs.size(), 28u);  // 30 minus colour 7 and depth 20
  EXPECT_EQ(pairer.pairs(), 28u);
  EXPECT_GE(pairer.dropped(), 2u);
}

TEST(FramePairer, RefusesPartnersFurtherApartThanTheBound) {
  FramePairer pairer(0.010);
  EXPECT_FALSE(pairer.AddColor(Frame(100000, 1)));
  EXPECT_FALSE(pairer.AddDepth(Frame(115000, 1)));  // 15 ms apart
  EXPECT_TRUE(pairer.AddColor(Frame(120000, 2)).has_value());  // 5 ms from the depth
}

}  // namespace
}  // namespace icgm
