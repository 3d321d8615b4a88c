#include "core/common/sample_summary.h"

#include <gtest/gtest.h>

namespace icgm {
namespace {

TEST(SampleSummaryTest, KnownSample) {
  std::vector<double> v;
  for (int i = 100; i >= 1; --i) v.push_back(i);  // 1..100, unsorted
  const SampleSummary s = Summarize(v);
  EXPECT_EQ(s.count, 100u);
  EXPECT_DOUBLE_EQ(s.mean, 50.5);
  EXPECT_DOUBLE_EQ(s.median, 50.5);
  EXPECT_DOUBLE_EQ(s.p95, 95.0);  // nearest rank of 0.95 * 99 = 94.05 -> index 94
  EXPECT_DOUBLE_EQ(s.max, 100.0);
  EXPECT_DOUBLE_EQ(Percentile(v, 0.0), 1.0);
  EXPECT_DOUBLE_EQ(Percentile(v, 1.0), 100.0);
}

TEST(SampleSummaryTest, OddCountAndEmpty) {
  EXPECT_DOUBLE_EQ(Summarize({3, 1, 2}).median, 2.0);
  const SampleSummary e = Summarize({});
  EXPECT_EQ(e.count, 0u);
  EXPECT_DOUBLE_EQ(e.max, 0.0);
  EXPECT_DOUBLE_EQ(Percentile({}, 0.5), 0.0);
}

}  // namespace
}  // namespace icgm
