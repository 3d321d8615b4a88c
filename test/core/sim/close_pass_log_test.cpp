// Close passes and who closed the gap, on hand-built motions with known shares, and on the
// closed-loop simulator's crowd around a standing robot.
#include "core/sim/close_pass_log.h"

#include <gtest/gtest.h>

#include <vector>

#include "core/sim/closed_loop_simulator.h"

namespace icgm::sim {
namespace {

constexpr double kDt = 0.1;
constexpr double kRobotRadius = 0.25;
constexpr double kWalkerRadius = 0.3;

// Robot and one walker moving with constant velocities for `seconds`.
ClosePassLog Drive(Eigen::Vector2d robot, const Eigen::Vector2d& robot_v, Eigen::Vector2d walker,
                   const Eigen::Vector2d& walker_v, double seconds) {
  ClosePassLog log;
  for (int k = 0; k * kDt < seconds; ++k) {
    const Eigen::Vector2d robot_next = robot + robot_v * kDt, walker_next = walker + walker_v * kDt;
    log.Step((k + 1) * kDt, robot, robot_next, robot_v.norm(), kRobotRadius, {walker},
             {walker_next}, {kWalkerRadius}, "step " + std::to_string(k));
    robot = robot_next;
    walker = walker_next;
  }
  return log;
}

TEST(ClosePassLogTest, RobotDrivingAtAStandingWalkerClosedTheGap) {
  // Footprint and body 0.55 m apart at contact; the robot stops 0.1 m short of the body.
  const ClosePassLog log = Drive({0.0, 0.0}, {0.5, 0.0}, {2.0, 0.0}, {0.0, 0.0}, 2.5);
  ASSERT_EQ(log.passes().size(), 1u);
  const ClosePass& p = log.passes()[0];
  EXPECT_FALSE(p.robot_standing);
  EXPECT_NEAR(p.min_clearance_m, 2.0 - 1.25 - 0.55, 1e-9);
  // From 1.0 m of clearance down to the closest point, all by the robot.
  EXPECT_NEAR(p.robot_closed_m, 1.0 - p.min_clearance_m, 0.05 + 1e-9);
  EXPECT_NEAR(p.walker_closed_m, 0.0, 1e-12);
  EXPECT_TRUE(p.robot_closed_more());
  EXPECT_EQ(log.robot_closed_more(), 1);
  // Below 0.3 m: 0.3 - 0.2 m, all by the robot.
  EXPECT_NEAR(p.robot_inside_m, 0.1, 1e-9);
  EXPECT_NEAR(p.walker_inside_m, 0.0, 1e-12);
  EXPECT_EQ(log.robot_inside_more(), 1);
  EXPECT_EQ(log.standing(), 0);
  // The episode began in the step that crossed 0.3 m: clearance 2.0 - 0.55 - 0.5 t < 0.3.
  EXPECT_NEAR(p.start_s, 2.3, 1e-9);
  EXPECT_EQ(p.context, "step 22");
}

TEST(ClosePassLogTest, WalkerWalkingIntoAStandingRobot) {
  const ClosePassLog log = Drive({0.0, 0.0}, {0.0, 0.0}, {0.0, 2.0}, {0.0, -1.0}, 1.35);
  ASSERT_EQ(log.passes().size(), 1u);
  const ClosePass& p = log.passes()[0];
  EXPECT_TRUE(p.robot_standing);
  EXPECT_NEAR(p.robot_closed_m, 0.0, 1e-12);
  EXPECT_GT(p.walker_closed_m, 0.9);
  EXPECT_NEAR(p.walker_inside_m, 0.3 - p.min_clearance_m, 1e-9);
  EXPECT_EQ(log.robot_inside_more(), 0);
  EXPECT_FALSE(p.robot_closed_more());
  EXPECT_EQ(log.standing(), 1);
  EXPECT_EQ(log.robot_closed_more(), 0);
}

TEST(ClosePassLogTest, WalkerClosingInOnARobotDrivingAcrossItsPath) {
  // The robot drives along x slowly; the walker comes down from above at walking pace.
  const ClosePassLog log = Drive({0.0, 0.0}, {0.1, 0.0}, {0.5, 2.0}, {0.0, -1.2}, 1.3);
  ASSERT_EQ(log.passes().size(), 1u);
  const ClosePass& p = log.passes()[0];
  EXPECT_FALSE(p.robot_standing);
  EXPECT_GT(p.walker_closed_m, 3.0 * p.robot_closed_m);
  EXPECT_GT(p.robot_closed_m, 0.0);  // the robot drove towards the walker's x
  EXPECT_FALSE(p.robot_closed_more());
}

TEST(ClosePassLogTest, WalkerPassingWideIsNoEpisodeAndTwoApproachesAreTwo) {
  // Passing 0.5 m from the footprint: none.
  EXPECT_TRUE(Drive({0.0, 0.0}, {0.0, 0.0}, {-3.0, 1.05}, {1.0, 0.0}, 6.0).passes().empty());
  // In (0.2 m), out, in again.
  ClosePassLog log;
  const Eigen::Vector2d robot(0.0, 0.0);
  const std::vector<double> y{1.5, 0.95, 0.75, 0.95, 1.5, 0.95, 0.8, 1.5};
  for (size_t k = 1; k < y.size(); ++k) {
    log.Step(k * kDt, robot, robot, 0.0, kRobotRadius, {{0.0, y[k - 1]}}, {{0.0, y[k]}},
             {kWalkerRadius}, "");
  }
  ASSERT_EQ(log.passes().size(), 2u);
  EXPECT_NEAR(log.passes()[0].min_clearance_m, 0.75 - 0.55, 1e-9);
  EXPECT_NEAR(log.passes()[1].min_clearance_m, 0.8 - 0.55, 1e-9);
  EXPECT_NEAR(log.min_clearance_m(), 0.2, 1e-9);
}

// The closed-loop simulator's walkers around a robot standing at its start for 60 s, every
// one of them non-yielding (they keep only their personal space, 0.3 m, from the footprint):
// none walks into the robot. Yielding walkers keep robot_clearance_m from it.
TEST(ClosePassLogTest, SimulatedWalkersDoNotWalkIntoAStandingRobot) {
  for (const double non_yielding : {1.0, 0.0}) {
    SimOptions o;
    o.seed = 7;
    o.crowd.num_pedestrians = 40;
    o.crowd.crossing_fraction = 1.0;
    o.crowd.non_yielding_fraction = non_yielding;
    o.crowd.personal_space_m = 0.3;
    ClosedLoopSimulator sim(o);
    ClosePassOptions options;
    options.clearance_m = 0.3 - 1e-3;  // walkers keep exactly 0.3 m, in float coordinates
    ClosePassLog log(options);
    std::vector<double> radii;
    for (size_t i = 0; i < sim.num_pedestrians(); ++i) radii.push_back(sim.pedestrian_radius_m(i));
    const auto positions = [&sim] {
      std::vector<Eigen::Vector2d> out;
      for (const auto& p : sim.pedestrians()) out.emplace_back(p.x_m, p.y_m);
      return out;
    };
    const Eigen::Vector2d robot(sim.planar_pose().x_m, sim.planar_pose().y_m);
    for (int k = 0; k < 600; ++k) {
      const auto before = positions();
      sim.Step(VelocityCommand(), kDt);
      log.Step(sim.elapsed_s(), robot, robot, 0.0, o.drive.robot_radius_m, before, positions(),
               radii, "");
    }
    EXPECT_TRUE(log.passes().empty()) << "non-yielding share " << non_yielding;
    // They do come close: the crossing walkers aim at the robot's view.
    EXPECT_LT(log.min_clearance_m(), non_yielding > 0 ? 0.35 : 0.75)
        << "non-yielding share " << non_yielding;
    EXPECT_GT(log.min_clearance_m(), non_yielding > 0 ? 0.299 : 0.3);
  }
}

}  // namespace
}  // namespace icgm::sim
