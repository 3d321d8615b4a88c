#include "core/slam/wheel_paced_queue.h"

#include <gtest/gtest.h>

#include <chrono>
#include <thread>

namespace icgm {
namespace {

Time T(double s) { return Time::FromSeconds(s); }

TEST(WheelPacedQueueTest, FrameWaitsForTheWheelSamplesAfterIt) {
  WheelFeed feed(0.05);
  WheelPacedQueueOptions o;
  o.max_wait_s = 0.3;
  WheelPacedQueue<int> queue(o, &feed);
  ASSERT_TRUE(queue.Push(T(10.0), 1));
  EXPECT_EQ(queue.ReadyFront(), nullptr);  // no wheel data yet
  feed.Add(T(10.02), Pose3::Identity());
  queue.Note(T(10.02));
  EXPECT_EQ(queue.ReadyFront(), nullptr);  // samples up to 10.05 not all in
  feed.Add(T(10.06), Pose3::Identity());
  queue.Note(T(10.06));
  ASSERT_NE(queue.ReadyFront(), nullptr);
  EXPECT_EQ(*queue.ReadyFront(), 1);
  EXPECT_EQ(queue.front_stamp(), T(10.0));
  queue.PopFront();
  EXPECT_TRUE(queue.empty());
}

TEST(WheelPacedQueueTest, NewerDataOrWallTimeEndTheWait) {
  WheelFeed feed(0.05);
  WheelPacedQueueOptions o;
  o.max_wait_s = 0.3;
  WheelPacedQueue<int> queue(o, &feed);
  queue.Push(T(5.0), 1);
  queue.Push(T(5.2), 2);
  EXPECT_EQ(queue.ReadyFront(), nullptr);
  queue.Push(T(5.3), 3);  // 0.3 s of newer frames: the wheels will not cover 5.0 in time
  ASSERT_NE(queue.ReadyFront(), nullptr);
  EXPECT_EQ(*queue.ReadyFront(), 1);
  queue.PopFront();
  EXPECT_EQ(queue.ReadyFront(), nullptr);  // 5.2 is 0.1 s behind the newest
  o.max_wait_s = 0.02;                     // the end of a bag: only wall time passes
  WheelPacedQueue<int> last(o, &feed);
  last.Push(T(6.0), 4);
  EXPECT_EQ(last.ReadyFront(), nullptr);
  std::this_thread::sleep_for(std::chrono::milliseconds(30));
  ASSERT_NE(last.ReadyFront(), nullptr);
}

TEST(WheelPacedQueueTest, WithoutWheelsAtOnceAndBounded) {
  WheelPacedQueueOptions o;
  o.wheels = false;
  o.max_pending = 2;
  WheelPacedQueue<int> queue(o, nullptr);
  EXPECT_TRUE(queue.Push(T(1.0), 1));
  EXPECT_TRUE(queue.Push(T(1.1), 2));
  EXPECT_FALSE(queue.Push(T(1.2), 3));  // the oldest made room
  EXPECT_EQ(queue.size(), 2u);
  ASSERT_NE(queue.ReadyFront(), nullptr);
  EXPECT_EQ(*queue.ReadyFront(), 2);
}

}  // namespace
}  // namespace icgm
