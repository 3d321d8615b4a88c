#include "core/odometry/hypothesis_evidence.h"

#include <algorithm>
#include <iterator>

#include <gtest/gtest.h>

namespace icgm {
namespace {

size_t Best(const std::vector<double>& scores) {
  return static_cast<size_t>(
      std::distance(scores.begin(), std::max_element(scores.begin(), scores.end())));
}

// Counts of frame 19 -> keyframe 17 of config/sim/handheld_crowd_deep.yaml (profile without the
// motion prior): the ICGM set (307 inliers, all static, 4 mm from the true step) against the
// set the ICGM set left out (26 inliers, 73 mm off), which explains more far-wall depth pixels
// but far fewer edges.
const std::vector<HypothesisEvidence> kStaticVsLeftOver = {{29572, 2353}, {32257, 1485}};

TEST(HypothesisEvidenceTest, RawSumLetsTheDepthCountDecide) {
  EXPECT_EQ(Best(EvidenceScores(kStaticVsLeftOver, false)), 1u);
  EXPECT_DOUBLE_EQ(EvidenceScores(kStaticVsLeftOver, false)[0], 29572.0 + 2353.0);
}

TEST(HypothesisEvidenceTest, NormalizedCuesLetTheEdgesTellTheMotionsApart) {
  const std::vector<double> s = EvidenceScores(kStaticVsLeftOver, true);
  EXPECT_EQ(Best(s), 0u);
  EXPECT_NEAR(s[0], 29572.0 / 32257.0 + 1.0, 1e-12);
  EXPECT_NEAR(s[1], 1.0 + 1485.0 / 2353.0, 1e-12);
}

TEST(HypothesisEvidenceTest, ACueNoHypothesisHasAddsNothing) {
  // Features extracted elsewhere without the colour image: no edge evidence at all.
  const std::vector<double> s = EvidenceScores({{100, 0}, {80, 0}}, true);
  EXPECT_DOUBLE_EQ(s[0], 1.0);
  EXPECT_DOUBLE_EQ(s[1], 0.8);
  EXPECT_TRUE(EvidenceScores({}, true).empty());
}

TEST(HypothesisEvidenceTest, AHypothesisBestInBothCuesWinsEitherWay) {
  const std::vector<HypothesisEvidence> h = {{500, 40}, {900, 70}, {700, 60}};
  EXPECT_EQ(Best(EvidenceScores(h, false)), 1u);
  EXPECT_EQ(Best(EvidenceScores(h, true)), 1u);
  EXPECT_DOUBLE_EQ(EvidenceScores(h, true)[1], 2.0);
}

}  // namespace
}  // namespace icgm
