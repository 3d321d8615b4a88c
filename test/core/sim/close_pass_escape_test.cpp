// The escape search on the closed-loop simulator's crowd: a robot driving on into
// non-yielding walkers comes within their personal space; from its state a little earlier,
// braking keeps the clearance, while driving on as it did does not.
#include "core/sim/close_pass_escape.h"

#include <gtest/gtest.h>

#include <deque>

namespace icgm::sim {
namespace {

TEST(ClosePassEscapeTest, BrakingInTimeKeepsTheClearanceDrivingOnDoesNot) {
  constexpr double kStepS = 0.1;
  SimOptions o;
  o.seed = 7;
  o.crowd.num_pedestrians = 40;
  o.crowd.crossing_fraction = 1.0;
  o.crowd.non_yielding_fraction = 1.0;
  o.crowd.personal_space_m = 0.3;
  ClosedLoopSimulator sim(o);
  const VelocityCommand drive{0.4, 0.0};
  std::deque<ClosedLoopSimulator> before;  // the simulator before each of the last steps
  bool passed = false;
  for (int k = 0; k < 100 && !passed; ++k) {
    before.push_back(sim);
    if (before.size() > 10) before.pop_front();
    sim.Step(drive, kStepS);
    ASSERT_GE(sim.StaticClearanceM(), 0.0) << "the drive must stay off the scenery";
    passed = sim.PedestrianClearanceM() < 0.299;
  }
  ASSERT_TRUE(passed) << "the scenario must bring a walker within 0.3 m of the footprint";
  ASSERT_EQ(before.size(), 10u);
  EscapeOptions options;
  const std::vector<EscapePlan> on{{"drive on", drive, 10.0, false}};
  const std::vector<EscapePlan> brake{{"brake", VelocityCommand(), 0.0, false}};
  // Driving on from the last step before the pass: the same pass (the copy repeats the run).
  EXPECT_EQ(FindEscape(before.back(), on, false, kStepS, options), -1);
  // Braking 1 s before: the walkers stop at their personal space, the robot stops short of it.
  EXPECT_EQ(FindEscape(before.front(), brake, false, 1.0, options), 0);
  // The whole set finds an escape from there too, forward-only; the plans list forward-only
  // ones first and backing off last.
  const std::vector<EscapePlan> plans = EscapePlans(options, 0.4);
  EXPECT_GE(FindEscape(before.front(), plans, false, 1.0, options), 0);
  EXPECT_FALSE(plans.front().reverses);
  EXPECT_TRUE(plans.back().reverses);
}

}  // namespace
}  // namespace icgm::sim
