#include "core/nav/navigation_phase.h"

#include <gtest/gtest.h>

namespace icgm {
namespace {

NavigationStatus Following(double to_goal_m) {
  NavigationStatus s;
  s.state = NavigationState::kActive;
  s.command.linear_mps = 0.4;
  s.distance_to_goal_m = to_goal_m;
  return s;
}

NavigationStatus Stopped(double to_goal_m) {
  NavigationStatus s = Following(to_goal_m);
  s.state = NavigationState::kSafetyStop;
  s.command = VelocityCommand();
  s.reason = "obstacle within 0.45 m ahead";
  return s;
}

TEST(DescribePhase, NamesEachStateInWords) {
  EXPECT_EQ(DescribePhase(Following(1.0)), "following the route");
  EXPECT_EQ(DescribePhase(Stopped(1.0)), "safety stop: obstacle within 0.45 m ahead");
  NavigationStatus s = Following(1.0);
  s.avoiding = true;
  EXPECT_EQ(DescribePhase(s), "avoiding an obstacle on the route");
  s.avoiding = false;
  s.rejoining = true;
  EXPECT_EQ(DescribePhase(s), "rejoining the route");
  s.reason = "yielding to a walker: brake";
  EXPECT_EQ(DescribePhase(s), "yielding to a walker: brake");
  s = Following(1.0);
  s.state = NavigationState::kAborted;
  s.reason = "no depth for 1.2 s > 1.0";
  EXPECT_EQ(DescribePhase(s), "aborted: no depth for 1.2 s > 1.0");
  s = Following(0.04);
  s.state = NavigationState::kTurningToGoal;
  s.goal_yaw_error_rad = 1.2;
  EXPECT_EQ(DescribePhase(s), "turning to the goal's orientation");
}

TEST(PhaseLog, ReportsAPhaseOnceItLastedAndNotAFlicker) {
  PhaseLog log(0.5, 10.0);
  EXPECT_FALSE(log.Update(0.0, Following(3.0)));
  const auto first = log.Update(0.5, Following(2.8));
  ASSERT_TRUE(first);
  EXPECT_EQ(*first, "following the route (2.80 m from the goal)");
  // A stop of two cycles (0.2 s) is not reported, nor the return to following.
  EXPECT_FALSE(log.Update(1.0, Stopped(2.5)));
  EXPECT_FALSE(log.Update(1.1, Stopped(2.5)));
  EXPECT_FALSE(log.Update(1.2, Following(2.4)));
  EXPECT_FALSE(log.Update(2.0, Following(2.0)));
  // A stop that lasts is reported when it has lasted min_s.
  EXPECT_FALSE(log.Update(3.0, Stopped(1.5)));
  EXPECT_FALSE(log.Update(3.4, Stopped(1.5)));
  const auto stop = log.Update(3.5, Stopped(1.5));
  ASSERT_TRUE(stop);
  EXPECT_EQ(*stop, "safety stop: obstacle within 0.45 m ahead (1.50 m from the goal)");
}

TEST(PhaseLog, RepeatsALongStopButNotFollowing) {
  PhaseLog log(0.5, 10.0);
  log.Update(0.0, Stopped(1.5));
  ASSERT_TRUE(log.Update(0.5, Stopped(1.5)));
  int reports = 0;
  std::string last;
  for (int k = 3; k <= 122; ++k) {  // every 0.25 s to 30.5 s
    if (const auto line = log.Update(0.25 * k, Stopped(1.5))) {
      ++reports;
      last = *line;
    }
  }
  EXPECT_EQ(reports, 3);  // at 10.5, 20.5 and 30.5 s
  EXPECT_EQ(last,
            "still safety stop: obstacle within 0.45 m ahead after 30.5 s (1.50 m from the goal)");
  PhaseLog following(0.5, 10.0);
  following.Update(0.0, Following(5.0));
  ASSERT_TRUE(following.Update(0.5, Following(5.0)));
  for (int k = 3; k <= 120; ++k) EXPECT_FALSE(following.Update(0.25 * k, Following(5.0)));
}

TEST(PhaseLog, ResetStartsANewGoalUnreported) {
  PhaseLog log(0.5, 10.0);
  log.Update(0.0, Following(3.0));
  ASSERT_TRUE(log.Update(0.5, Following(3.0)));
  log.Reset();
  EXPECT_FALSE(log.Update(1.0, Following(3.0)));
  EXPECT_TRUE(log.Update(1.5, Following(3.0)));
}

}  // namespace
}  // namespace icgm
