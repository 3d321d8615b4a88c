#include "core/eval/error_stats.h"

#include <cmath>

#include <gtest/gtest.h>

namespace icgm {
namespace {

TEST(ErrorStatsTest, KnownValues) {
  const ErrorStats s = ComputeErrorStats({3.0, 1.0, 4.0, 2.0});
  EXPECT_EQ(s.count, 4u);
  EXPECT_DOUBLE_EQ(s.mean, 2.5);
  EXPECT_DOUBLE_EQ(s.median, 2.5);
  EXPECT_DOUBLE_EQ(s.rmse, std::sqrt(30.0 / 4.0));
  EXPECT_DOUBLE_EQ(s.std_dev, std::sqrt(1.25));
  EXPECT_DOUBLE_EQ(s.min, 1.0);
  EXPECT_DOUBLE_EQ(s.max, 4.0);
  EXPECT_DOUBLE_EQ(ComputeErrorStats({5.0, 1.0, 9.0}).median, 5.0);
}

TEST(ErrorStatsTest, EmptyIsAllZero) {
  const ErrorStats s = ComputeErrorStats({});
  EXPECT_EQ(s.count, 0u);
  EXPECT_EQ(s.rmse, 0.0);
  EXPECT_EQ(s.max, 0.0);
}

}  // namespace
}  // namespace icgm
