#include "core/dataset/stamp_association.h"

#include <cmath>
#include <random>
#include <set>

#include <gtest/gtest.h>

namespace icgm {
namespace {

std::vector<Time> Seconds(const std::vector<double>& s) {
  std::vector<Time> out;
  for (double v : s) out.push_back(Time::FromSeconds(v));
  return out;
}

using Pairs = std::vector<std::pair<size_t, size_t>>;

TEST(AssociateStampsTest, ClosestPairsWinAndEachStampIsUsedOnce) {
  const auto a = Seconds({1.000, 2.000, 2.010, 3.000});
  const auto b = Seconds({1.019, 1.985, 2.008, 3.021});
  EXPECT_EQ(AssociateStamps(a, b, 0.02), (Pairs{{0, 0}, {1, 1}, {2, 2}}));
  EXPECT_EQ(AssociateStamps(a, b, 0.0021), (Pairs{{2, 2}}));
  EXPECT_EQ(AssociateStamps(a, b, 0.05), (Pairs{{0, 0}, {1, 1}, {2, 2}, {3, 3}}));
  EXPECT_TRUE(AssociateStamps(a, {}, 1.0).empty());
  EXPECT_TRUE(AssociateStamps({}, b, 1.0).empty());
}

TEST(AssociateStampsTest, RecoversJitteredPairing) {
  // b is a copy of a with jitter well below half the spacing: every pair is found.
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> jitter(-0.004, 0.004);
  std::vector<double> sa, sb;
  for (int i = 0; i < 500; ++i) {
    sa.push_back(100.0 + 0.033 * i);
    sb.push_back(sa.back() + jitter(rng));
  }
  const Pairs p = AssociateStamps(Seconds(sa), Seconds(sb), 0.01);
  ASSERT_EQ(p.size(), 500u);
  for (size_t i = 0; i < p.size(); ++i) EXPECT_EQ(p[i], std::make_pair(i, i));
}

TEST(AssociateStampsTest, ExactlyAtTheLimitIsAccepted) {
  EXPECT_EQ(AssociateStamps(Seconds({5.0}), Seconds({5.02}), 0.02).size(), 1u);
  EXPECT_EQ(AssociateStamps(Seconds({5.0}), Seconds({5.020001}), 0.02).size(), 0u);
}

TEST(AssociateStampsTest, ExtremeWindowsAreClamped) {
  const auto a = Seconds({1.0, 2.0});
  const auto b = Seconds({1.0, 500.0});
  EXPECT_EQ(AssociateStamps(a, b, -1.0), (Pairs{{0, 0}}));  // equal stamps only
  EXPECT_EQ(AssociateStamps(a, b, std::nan("")), (Pairs{{0, 0}}));
  EXPECT_EQ(AssociateStamps(a, b, 1e300), (Pairs{{0, 0}, {1, 1}}));
  EXPECT_EQ(AssociateStamps(a, b, HUGE_VAL), (Pairs{{0, 0}, {1, 1}}));
}

}  // namespace
}  // namespace icgm
