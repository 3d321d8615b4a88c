// A short closed-loop drive: the Navigator's commands drive the ClosedLoopSimulator's robot in
// the cafeteria along the first metres of the scenario's route (exact pose, rendered depth for
// the obstacle grid). It must reach the goal without touching anything, close to the route.
#include <gtest/gtest.h>

#include "core/nav/navigator.h"
#include "core/sim/closed_loop_simulator.h"
#include "core/sim/sim_options.h"

namespace icgm {
namespace {

struct DriveOutcome {
  NavigationStatus status;
  double max_cross_track_m = 0.0;
  double goal_error_m = 0.0;
  int collisions = 0;
  double elapsed_s = 0.0;
};

DriveOutcome Drive(int num_pedestrians, double length_m, double max_s) {
  sim::SimOptions options =
      sim::LoadSimOptions(std::string(ICGM_SOURCE_DIR) + "/config/sim/nav_cafeteria.yaml");
  options.crowd.num_pedestrians = num_pedestrians;
  sim::ClosedLoopSimulator sim(options);
  NavigationOptions nav_options;
  nav_options.navigator.robot_radius_m = options.drive.robot_radius_m;
  Navigator nav(nav_options);
  const sim::PlanarPose start = sim.planar_pose();
  const Eigen::Vector2d heading(std::cos(start.yaw_rad), std::sin(start.yaw_rad));
  const Eigen::Vector2d a(start.x_m, start.y_m);
  const Eigen::Vector2d goal = a + length_m * heading;
  EXPECT_TRUE(nav.SetRoute({a, goal}));
  DriveOutcome out;
  const double dt = 0.1;
  for (double t = 0.0; t < max_s; t += dt) {
    const sim::SimFrame f = sim.Render();
    nav.UpdatePose(f.stamp, f.T_world_base, t == 0.0);
    EXPECT_TRUE(nav.UpdateDepth(f.stamp, f.depth_m, sim.intrinsics(), sim.T_base_camera()));
    out.status = nav.Update(f.stamp, dt);
    out.max_cross_track_m = std::max(out.max_cross_track_m, out.status.cross_track_m);
    if (out.status.state == NavigationState::kReached ||
        out.status.state == NavigationState::kAborted) {
      break;
    }
    sim.Step(out.status.command, dt);
  }
  out.goal_error_m = (Eigen::Vector2d(sim.planar_pose().x_m, sim.planar_pose().y_m) - goal).norm();
  out.collisions = sim.collisions();
  out.elapsed_s = sim.elapsed_s();
  return out;
}

TEST(ClosedLoopDriveTest, ReachesTheGoalAlongAnEmptyRoute) {
  const DriveOutcome r = Drive(0, 4.0, 25.0);
  EXPECT_EQ(r.status.state, NavigationState::kReached) << r.status.reason;
  EXPECT_LE(r.goal_error_m, 0.25);
  EXPECT_EQ(r.collisions, 0);
  EXPECT_LT(r.max_cross_track_m, 0.03);
  EXPECT_LT(r.elapsed_s, 4.0 / 0.3);  // at least 0.3 m/s on average
}

TEST(ClosedLoopDriveTest, ReachesTheGoalAmongAFewWalkers) {
  const DriveOutcome r = Drive(6, 4.0, 40.0);
  EXPECT_EQ(r.status.state, NavigationState::kReached) << r.status.reason;
  EXPECT_LE(r.goal_error_m, 0.25);
  EXPECT_EQ(r.collisions, 0);
  EXPECT_LT(r.max_cross_track_m, 1.5);  // detours stay near the route
}

}  // namespace
}  // namespace icgm
