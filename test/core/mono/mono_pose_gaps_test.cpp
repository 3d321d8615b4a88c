// Frames without a pose by cause, on a hand-built run: start-up, a loss tracked again, a loss
// that ends in a reset, the re-initialization (its reference frame posed afterwards), a loss at
// the end.
#include <gtest/gtest.h>

#include "core/mono/mono_pose_gaps.h"

namespace icgm {
namespace {

Time GapStampOf(size_t i) { return Time::FromSeconds(1.0 + i / 30.0); }

MonoFrameResult GapFrame(size_t i, MonoState state, bool has_pose) {
  MonoFrameResult r;
  r.frame_index = i;
  r.stamp = GapStampOf(i);
  r.state = state;
  r.has_pose = has_pose;
  return r;
}

MonoFrameResult GapInitialized(size_t i, size_t reference) {
  MonoFrameResult r = GapFrame(i, MonoState::kTracking, true);
  r.initialized = true;
  r.reference_stamp = GapStampOf(reference);
  return r;
}

TEST(MonoPoseGapsTest, FramesWithoutPoseAreCountedByCause) {
  MonoPoseGapCounter c;
  c.Add(GapFrame(0, MonoState::kInitializing, false));
  c.Add(GapFrame(1, MonoState::kInitializing, false));
  c.Add(GapInitialized(2, 1));  // frame 1 is posed now
  c.Add(GapFrame(3, MonoState::kTracking, true));
  c.Add(GapFrame(4, MonoState::kLost, false));
  c.Add(GapFrame(5, MonoState::kLost, false));
  c.Add(GapFrame(6, MonoState::kTracking, true));  // found again
  for (size_t i = 7; i <= 9; ++i) c.Add(GapFrame(i, MonoState::kLost, false));
  MonoFrameResult reset = GapFrame(10, MonoState::kInitializing, false);
  reset.reset = true;
  c.Add(reset);
  for (size_t i = 11; i <= 13; ++i) c.Add(GapFrame(i, MonoState::kInitializing, false));
  c.Add(GapInitialized(14, 10));  // the reset frame was the new map's reference
  c.Add(GapFrame(15, MonoState::kLost, false));

  const MonoFramesWithoutPose all = c.Counts();
  EXPECT_EQ(all.not_initialized, 1u);
  EXPECT_EQ(all.lost, 3u);
  EXPECT_EQ(all.lost_then_reset, 3u);
  EXPECT_EQ(all.reinitializing, 3u);
  EXPECT_EQ(all.total(), 10u);

  // Between the first map's last pose (frame 6) and the new map's reference frame (10).
  const MonoFramesWithoutPose join = c.CountsBetween(GapStampOf(6), GapStampOf(10));
  EXPECT_EQ(join.lost_then_reset, 3u);
  EXPECT_EQ(join.reinitializing, 0u);
  EXPECT_EQ(join.lost, 0u);
  EXPECT_EQ(c.CountsBetween(GapStampOf(10), GapStampOf(14)).reinitializing, 3u);
}

}  // namespace
}  // namespace icgm
