#include "core/slam/in_flight_limit.h"

#include <gtest/gtest.h>

#include <deque>

namespace icgm {
namespace {

using Clock = InFlightLimit::Clock;
using Ms = std::chrono::milliseconds;

Time Frame(int i) { return Time::FromNanoseconds(1'000'000'000LL + i * 33'333'333LL); }

TEST(InFlightLimitTest, AdmitsEverythingUntilTheConsumerAnswers) {
  InFlightLimitOptions o;
  o.max_frames = 2;
  InFlightLimit limit(o);
  const Clock::time_point t0 = Clock::now();
  for (int i = 0; i < 10; ++i) EXPECT_TRUE(limit.Admit(Frame(i), t0 + Ms(i))) << i;
  EXPECT_FALSE(limit.active());
  EXPECT_EQ(limit.skipped(), 0u);
  limit.Answered(Frame(8), t0 + Ms(10));  // answers 0..8 (the first and dropped ones have none)
  EXPECT_TRUE(limit.active());
  EXPECT_EQ(limit.in_flight(), 1u);
  EXPECT_TRUE(limit.Admit(Frame(10), t0 + Ms(11)));
  EXPECT_FALSE(limit.Admit(Frame(11), t0 + Ms(12)));  // 9 and 10 in flight
  EXPECT_EQ(limit.skipped(), 1u);
  limit.Answered(Frame(9), t0 + Ms(13));
  EXPECT_TRUE(limit.Admit(Frame(12), t0 + Ms(14)));
  EXPECT_EQ(limit.admitted(), 12u);
}

TEST(InFlightLimitTest, ZeroIsNoLimit) {
  InFlightLimitOptions o;
  o.max_frames = 0;
  InFlightLimit limit(o);
  const Clock::time_point t0 = Clock::now();
  limit.Answered(Frame(0), t0);
  for (int i = 1; i < 50; ++i) EXPECT_TRUE(limit.Admit(Frame(i), t0 + Ms(i)));
  EXPECT_EQ(limit.skipped(), 0u);
}

TEST(InFlightLimitTest, StalledConsumerOrRestartedReplayForgetsTheFramesInFlight) {
  InFlightLimitOptions o;
  o.max_frames = 2;
  o.stall_s = 0.5;
  InFlightLimit limit(o);
  const Clock::time_point t0 = Clock::now();
  limit.Answered(Frame(0), t0);
  EXPECT_TRUE(limit.Admit(Frame(1), t0 + Ms(10)));
  EXPECT_TRUE(limit.Admit(Frame(2), t0 + Ms(20)));
  EXPECT_FALSE(limit.Admit(Frame(3), t0 + Ms(400)));  // waiting, not yet stalled
  EXPECT_TRUE(limit.Admit(Frame(4), t0 + Ms(520)));   // 0.51 s since frame 1: stalled
  EXPECT_EQ(limit.forgotten(), 2u);
  EXPECT_EQ(limit.in_flight(), 1u);
  // After a pause the frames admitted again are not taken for a stall.
  limit.Answered(Frame(4), t0 + Ms(530));
  EXPECT_TRUE(limit.Admit(Frame(5), t0 + Ms(5000)));
  EXPECT_TRUE(limit.Admit(Frame(6), t0 + Ms(5010)));
  EXPECT_FALSE(limit.Admit(Frame(7), t0 + Ms(5020)));
  EXPECT_EQ(limit.forgotten(), 2u);
  // A replay from the start: its stamps go back.
  EXPECT_TRUE(limit.Admit(Frame(0), t0 + Ms(5030)));
  EXPECT_EQ(limit.forgotten(), 4u);
  EXPECT_EQ(limit.in_flight(), 1u);
}

TEST(InFlightLimitTest, RejectsBadOptions) {
  InFlightLimitOptions o;
  EXPECT_TRUE(Validate(o).ok());
  o.max_frames = -1;
  EXPECT_FALSE(Validate(o).ok());
  o.max_frames = 1;
  o.stall_s = 0.0;
  EXPECT_FALSE(Validate(o).ok());
}

// A producer (2 ms per frame) feeding a consumer slower than the frames come (10 ms per frame,
// frames every 4 ms) through a queue of 10 that drops its oldest frame when full, the consumer
// answering each frame it finishes. Without a limit most produced frames are thrown away by the
// queue after the producer spent its time on them; with the limit no produced frame is thrown
// away and the consumer answers as many frames.
struct PipelineRun {
  int produced = 0;
  int answered = 0;
  int answered_while_frames_come = 0;
  int dropped_after_production = 0;
  int skipped = 0;
};

PipelineRun RunPipeline(int max_frames) {
  InFlightLimitOptions o;
  o.max_frames = max_frames;
  InFlightLimit limit(o);
  const Clock::time_point t0 = Clock::now();
  std::deque<int> queue;   // produced frames waiting for the consumer
  int busy_until_ms = -1;  // consumer
  int current = -1;
  PipelineRun run;
  const int frames = 300, interval_ms = 4, produce_ms = 2, consume_ms = 10;
  int producer_free_ms = 0;
  for (int now = 0; now < frames * interval_ms + 2000; ++now) {
    if (current >= 0 && now >= busy_until_ms) {  // the consumer finishes and answers
      limit.Answered(Frame(current), t0 + Ms(now));
      ++run.answered;
      run.answered_while_frames_come += now < frames * interval_ms;
      current = -1;
    }
    if (current < 0 && !queue.empty()) {
      current = queue.front();
      queue.pop_front();
      busy_until_ms = now + consume_ms;
    }
    if (now % interval_ms == 0 && now / interval_ms < frames && now >= producer_free_ms) {
      const int i = now / interval_ms;
      if (!limit.Admit(Frame(i), t0 + Ms(now))) continue;
      ++run.produced;
      producer_free_ms = now + produce_ms;
      queue.push_back(i);  // (the frame reaches the queue when produced; order is what counts)
      if (queue.size() > 10) {
        queue.pop_front();
        ++run.dropped_after_production;
      }
    }
  }
  run.skipped = static_cast<int>(limit.skipped());
  return run;
}

TEST(InFlightLimitTest, SlowConsumerNoFrameProducedInVain) {
  const PipelineRun unlimited = RunPipeline(0);
  const PipelineRun limited = RunPipeline(3);
  EXPECT_EQ(unlimited.produced, 300);
  EXPECT_GT(unlimited.dropped_after_production, 100);
  EXPECT_EQ(limited.dropped_after_production, 0);
  EXPECT_EQ(limited.produced, limited.answered);
  EXPECT_EQ(limited.produced + limited.skipped, 300);
  // The consumer is as busy either way: one answer per 10 ms while frames come (after them the
  // unlimited queue still holds up to 10 frames, the limited one 3).
  EXPECT_GE(limited.answered_while_frames_come, unlimited.answered_while_frames_come - 1);
  EXPECT_GE(limited.answered_while_frames_come, 300 * 4 / 10 - 2);
}

}  // namespace
}  // namespace icgm
