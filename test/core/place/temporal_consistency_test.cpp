#include "core/place/temporal_consistency.h"

#include <gtest/gtest.h>

namespace icgm {
namespace {

TEST(TemporalConsistencyTest, OffAcceptsEveryHypothesis) {
  TemporalConsistency t(TemporalConsistencyOptions{});  // consistent_queries 0
  EXPECT_TRUE(t.Consistent(50, 3));
  t.Record(50, {3});
  EXPECT_TRUE(t.Consistent(51, 40));
}

TEST(TemporalConsistencyTest, OneQueryMustAgreeOnANeighbouringPlace) {
  TemporalConsistencyOptions o;
  o.consistent_queries = 1;
  o.window_images = 2;
  TemporalConsistency t(o);
  // Query 40 revisits image 10 (hypotheses 10 and 25); query 41 continues the revisit.
  EXPECT_FALSE(t.Consistent(40, 10)) << "the first query of a revisit has no support";
  t.Record(40, {10, 25});
  EXPECT_TRUE(t.Consistent(41, 11));
  EXPECT_TRUE(t.Consistent(41, 12));
  EXPECT_TRUE(t.Consistent(41, 27)) << "the second hypothesis of query 40 supports 27";
  EXPECT_FALSE(t.Consistent(41, 13)) << "3 images from every hypothesis of query 40";
  EXPECT_FALSE(t.Consistent(41, 60));
  // A gap (query 41 recorded nothing) breaks the chain for query 42.
  t.Record(41, {});
  EXPECT_FALSE(t.Consistent(42, 12));
  // Support must come from the query just before, not an older one.
  EXPECT_FALSE(t.Consistent(43, 10)) << "query 42 was never recorded";
}

TEST(TemporalConsistencyTest, TwoQueriesMustBothAgree) {
  TemporalConsistencyOptions o;
  o.consistent_queries = 2;
  o.window_images = 1;
  TemporalConsistency t(o);
  t.Record(20, {5});
  t.Record(21, {6});
  EXPECT_TRUE(t.Consistent(22, 6));   // |6-5| = 1 and |6-6| = 0
  EXPECT_FALSE(t.Consistent(22, 7));  // |7-5| = 2 > 1
  t.Record(22, {30});                 // a look-alike for query 22
  EXPECT_FALSE(t.Consistent(23, 7)) << "query 22 disagrees";
  EXPECT_FALSE(t.Consistent(23, 31)) << "query 21 disagrees with the look-alike chain";
}

}  // namespace
}  // namespace icgm
