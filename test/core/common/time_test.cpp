#include "core/common/time.h"

#include <gtest/gtest.h>

namespace icgm {
namespace {

TEST(TimeTest, ParsesTumTimestampExactly) {
  Time t;
  ASSERT_TRUE(Time::Parse("1305031102.175304", &t));
  EXPECT_EQ(t.nanoseconds(), 1305031102175304000LL);
  EXPECT_EQ(t.ToString(), "1305031102.175304");
}

TEST(TimeTest, RejectsGarbage) {
  Time t;
  EXPECT_FALSE(Time::Parse("", &t));
  EXPECT_FALSE(Time::Parse("12a.5", &t));
  EXPECT_FALSE(Time::Parse(".", &t));
}

TEST(TimeTest, RoundsWhenPrinting) {
  EXPECT_EQ(Time::FromNanoseconds(1999999999).ToString(6), "2.000000");
  EXPECT_EQ(Time::FromNanoseconds(1500000).ToString(3), "0.002");
  EXPECT_EQ(Time::FromNanoseconds(-1500000000).ToString(1), "-1.5");
}

TEST(TimeTest, DurationAndOrdering) {
  const Time a = Time::FromSeconds(10.25);
  const Time b = Time::FromSeconds(10.0);
  EXPECT_NEAR(DurationSeconds(a, b), 0.25, 1e-12);
  EXPECT_TRUE(b < a);
  EXPECT_FALSE(a < b);
}

}  // namespace
}  // namespace icgm
