// Prefetched frames arrive in order and equal directly rendered ones.
#include "core/sim/frame_prefetcher.h"

#include <gtest/gtest.h>

#include <cstring>

namespace icgm::sim {
namespace {

SimOptions Tiny() {
  SimOptions o;
  o.num_frames = 9;
  o.room.num_tables = 4;
  o.crowd.num_pedestrians = 10;
  return o;
}

bool SameBytes(const cv::Mat& a, const cv::Mat& b) {
  return a.size() == b.size() && a.type() == b.type() &&
         std::memcmp(a.data, b.data, a.total() * a.elemSize()) == 0;
}

TEST(FramePrefetcherTest, DeliversEveryFrameInOrderIdenticalToRender) {
  const Simulator sim(Tiny());
  FramePrefetcher prefetcher(sim, 2);
  SimFrame f;
  size_t n = 0;
  while (prefetcher.Next(&f)) {
    ASSERT_EQ(f.index, n);
    const SimFrame direct = sim.Render(n);
    EXPECT_EQ(f.stamp, direct.stamp);
    EXPECT_TRUE(SameBytes(f.bgr, direct.bgr));
    EXPECT_TRUE(SameBytes(f.depth_m, direct.depth_m));
    EXPECT_TRUE(SameBytes(f.dynamic_mask, direct.dynamic_mask));
    ++n;
  }
  EXPECT_EQ(n, sim.size());
  EXPECT_FALSE(prefetcher.Next(&f));
}

TEST(FramePrefetcherTest, StopsCleanlyWhenAbandonedEarly) {
  const Simulator sim(Tiny());
  SimFrame f;
  {
    FramePrefetcher prefetcher(sim, 3);
    ASSERT_TRUE(prefetcher.Next(&f));
  }  // destructor joins the worker while it is blocked on a full buffer
  EXPECT_EQ(f.index, 0u);
}

}  // namespace
}  // namespace icgm::sim
