#include "core/slam/wheel_feed.h"

#include <vector>

#include <gtest/gtest.h>

namespace icgm {
namespace {

Pose3 At(double x) { return MakePose({x, 0, 0}, Quat::Identity()); }

// A frame at t gets every sample up to t + lead, once, oldest first; it is covered once a
// sample at or after t + lead arrived.
TEST(WheelFeedTest, FeedsSamplesUpToTheLeadOnceInOrder) {
  WheelFeed feed(0.05);
  EXPECT_FALSE(feed.Covers(Time::FromSeconds(1.0)));
  for (double t : {0.98, 1.00, 1.02, 1.04}) EXPECT_TRUE(feed.Add(Time::FromSeconds(t), At(t)));
  EXPECT_FALSE(feed.Covers(Time::FromSeconds(1.0)));  // 1.05 not reached
  EXPECT_TRUE(feed.Add(Time::FromSeconds(1.05), At(1.05)));
  EXPECT_TRUE(feed.Covers(Time::FromSeconds(1.0)));
  EXPECT_TRUE(feed.Add(Time::FromSeconds(1.06), At(1.06)));
  std::vector<double> fed;
  const auto sink = [&](Time t, const Pose3& p) {
    fed.push_back(t.seconds());
    EXPECT_DOUBLE_EQ(p.translation().x(), t.seconds());
  };
  feed.FeedUpTo(Time::FromSeconds(1.0), sink);
  ASSERT_EQ(fed.size(), 5u);
  EXPECT_NEAR(fed.back(), 1.05, 1e-9);
  feed.FeedUpTo(Time::FromSeconds(1.0), sink);  // nothing twice
  EXPECT_EQ(fed.size(), 5u);
  feed.FeedUpTo(Time::FromSeconds(1.1), sink);
  EXPECT_EQ(fed.size(), 6u);
}

TEST(WheelFeedTest, RefusesOutOfOrderSamplesAndBoundsThePending) {
  WheelFeed feed(0.05, 3);
  EXPECT_FALSE(feed.received_any());
  EXPECT_TRUE(feed.Add(Time::FromSeconds(2.0), At(2.0)));
  EXPECT_FALSE(feed.Add(Time::FromSeconds(2.0), At(2.0)));
  EXPECT_FALSE(feed.Add(Time::FromSeconds(1.0), At(1.0)));
  for (double t : {2.1, 2.2, 2.3}) EXPECT_TRUE(feed.Add(Time::FromSeconds(t), At(t)));
  std::vector<double> fed;
  feed.FeedUpTo(Time::FromSeconds(3.0), [&](Time t, const Pose3&) { fed.push_back(t.seconds()); });
  ASSERT_EQ(fed.size(), 3u);  // 2.0 dropped: more than 3 pending
  EXPECT_NEAR(fed.front(), 2.1, 1e-9);
}

}  // namespace
}  // namespace icgm
