// The closed-loop simulator executes velocity commands as a differential-drive base would
// (limits, noise), integrates wheel odometry with its error model, lets the crowd react to the
// robot's current pose, counts contacts of the footprint, and renders what its ground truth says.
#include "core/sim/closed_loop_simulator.h"
#include "core/sim/scan_render.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <memory>
#include <optional>
#include <vector>

#include <opencv2/core.hpp>

namespace icgm::sim {
namespace {

// An empty 20 m x 20 m room (no furniture, no pedestrians), noise-free drive and odometry.
SimOptions EmptyRoom() {
  SimOptions o;
  o.seed = 5;
  o.room.num_tables = 0;
  o.room.num_shelves = 0;
  o.room.num_pillars = 0;
  o.crowd.num_pedestrians = 0;
  o.drive.linear_noise_fraction = 0.0;
  o.drive.angular_noise_fraction = 0.0;
  o.odometry = OdometryNoiseOptions{0.0, 0.0, 0.0, 0.0};
  return o;
}

constexpr double kDt = 0.1;

void Drive(ClosedLoopSimulator* sim, const VelocityCommand& cmd, double seconds) {
  const int steps = static_cast<int>(std::lround(seconds / kDt));
  for (int i = 0; i < steps; ++i) sim->Step(cmd, kDt);
}

TEST(ClosedLoopSimulatorTest, StartsAtTheRouteStartLikeTheFixedRouteSimulator) {
  SimOptions o = EmptyRoom();
  o.room.num_tables = 10;
  o.crowd.num_pedestrians = 5;
  o.num_frames = 2;
  const Simulator fixed(o);
  const ClosedLoopSimulator sim(o);
  EXPECT_NEAR(sim.planar_pose().x_m, fixed.planar_pose(0).x_m, 1e-12);
  EXPECT_NEAR(sim.planar_pose().y_m, fixed.planar_pose(0).y_m, 1e-12);
  EXPECT_NEAR(sim.planar_pose().yaw_rad, fixed.planar_pose(0).yaw_rad, 1e-12);
  EXPECT_TRUE(sim.T_world_camera().isApprox(fixed.T_world_camera(0), 1e-12));
  EXPECT_EQ(sim.stamp(), fixed.stamp(0));
  // Same world: same furniture.
  ASSERT_EQ(sim.scene().boxes.size(), fixed.scene().boxes.size());
  for (size_t i = 0; i < sim.scene().boxes.size(); ++i) {
    EXPECT_EQ(sim.scene().boxes[i].min_m, fixed.scene().boxes[i].min_m);
  }
  // Same crowd at the start (the robot is at rest at the same pose).
  const std::vector<PedestrianState> people = sim.pedestrians();
  ASSERT_EQ(people.size(), fixed.crowd().num_pedestrians());
  for (size_t i = 0; i < people.size(); ++i) {
    EXPECT_EQ(people[i].x_m, fixed.crowd().state(0, i).x_m);
    EXPECT_EQ(people[i].y_m, fixed.crowd().state(0, i).y_m);
  }
}

TEST(ClosedLoopSimulatorTest, DrivingStraightCoversSpeedTimesTime) {
  SimOptions o = EmptyRoom();
  o.drive.linear_noise_fraction = 0.05;
  o.drive.angular_noise_fraction = 0.05;
  const PlanarPose start{4.0, 10.0, 0.0};
  ClosedLoopSimulator sim(o, start);
  const double v = 0.5, t = 10.0;
  Drive(&sim, {v, 0.0}, t);
  // The ramp-up at max_linear_accel_mps2 (speed rising by a * dt per step) loses
  // v^2 / (2 a) - v dt / 2 against v * t.
  const double expected = v * t - v * v / (2.0 * o.drive.max_linear_accel_mps2) + 0.5 * v * kDt;
  const double dx = sim.planar_pose().x_m - start.x_m;
  // 100 steps with 5% independent noise each: sigma of the mean ~0.5%.
  EXPECT_NEAR(dx, expected, 0.02 * expected);
  EXPECT_GT(std::abs(dx - expected), 1e-6);  // the actuation noise is there
  // The noise is relative: none on a zero turn rate.
  EXPECT_NEAR(sim.planar_pose().y_m, start.y_m, 1e-9);
  EXPECT_NEAR(sim.planar_pose().yaw_rad, 0.0, 1e-12);
  EXPECT_NEAR(sim.distance_driven_m(), dx, 1e-9);
  EXPECT_NEAR(sim.elapsed_s(), t, 1e-9);
  EXPECT_EQ(sim.num_steps(), 100u);
  EXPECT_NEAR(DurationSeconds(sim.stamp(), Time::FromSeconds(o.start_time_s)), t, 1e-6);
}

TEST(ClosedLoopSimulatorTest, SpeedAndAccelerationLimitsHold) {
  SimOptions o = EmptyRoom();
  o.drive.max_linear_mps = 0.8;
  o.drive.max_linear_accel_mps2 = 0.5;
  o.drive.max_angular_radps = 1.0;
  o.drive.max_angular_accel_radps2 = 2.0;
  ClosedLoopSimulator sim(o, PlanarPose{10.0, 10.0, 0.0});
  double v_prev = 0.0, w_prev = 0.0, v_max = 0.0;
  int steps_to_full_speed = -1;
  for (int i = 0; i < 40; ++i) {
    sim.Step({5.0, -5.0}, kDt);
    const double v = sim.true_velocity().linear_mps, w = sim.true_velocity().angular_radps;
    EXPECT_LE(std::abs(v - v_prev), 0.5 * kDt + 1e-12);
    EXPECT_LE(std::abs(w - w_prev), 2.0 * kDt + 1e-12);
    EXPECT_LE(v, 0.8 + 1e-12);
    EXPECT_GE(w, -1.0 - 1e-12);
    if (steps_to_full_speed < 0 && v >= 0.8 - 1e-12) steps_to_full_speed = i + 1;
    v_max = std::max(v_max, v);
    v_prev = v;
    w_prev = w;
  }
  EXPECT_EQ(steps_to_full_speed, 16);  // 0.8 m/s at 0.5 m/s^2: 1.6 s
  EXPECT_NEAR(w_prev, -1.0, 1e-12);
  // Braking is limited too.
  sim.Step({0.0, 0.0}, kDt);
  EXPECT_NEAR(sim.true_velocity().linear_mps, 0.8 - 0.05, 1e-12);
  EXPECT_NEAR(sim.true_velocity().angular_radps, -1.0 + 0.2, 1e-12);
}

TEST(ClosedLoopSimulatorTest, TurnsInPlace) {
  const SimOptions o = EmptyRoom();
  const PlanarPose start{10.0, 10.0, 0.3};
  ClosedLoopSimulator sim(o, start);
  double yaw = start.yaw_rad;
  for (int i = 0; i < 20; ++i) {
    sim.Step({0.0, 1.2}, kDt);
    yaw += sim.true_velocity().angular_radps * kDt;
  }
  EXPECT_NEAR(sim.true_velocity().angular_radps, 1.2, 1e-12);
  EXPECT_NEAR(sim.planar_pose().x_m, start.x_m, 1e-12);
  EXPECT_NEAR(sim.planar_pose().y_m, start.y_m, 1e-12);
  EXPECT_NEAR(std::remainder(sim.planar_pose().yaw_rad - yaw, 2 * M_PI), 0.0, 1e-9);
  // Ramp at 3 rad/s^2: steps at 0.3, 0.6, 0.9, then 17 steps at 1.2 rad/s: 0.18 + 2.04 rad.
  EXPECT_NEAR(std::remainder(sim.planar_pose().yaw_rad - start.yaw_rad, 2 * M_PI), 2.22, 1e-9);
  // Wheel odometry sees the rotation (no distance driven: no distance-dependent error).
  const Pose3 odom = sim.odometry().T_odom_base;
  EXPECT_NEAR(std::atan2(odom(1, 0), odom(0, 0)), 2.22, 1e-9);
  EXPECT_NEAR(odom.translation().norm(), 0.0, 1e-12);
}

TEST(ClosedLoopSimulatorTest, WheelOdometryFollowsTheErrorModel) {
  SimOptions o = EmptyRoom();
  o.odometry.scale_error = 0.05;
  o.odometry.heading_bias_rad_per_m = 0.01;
  ClosedLoopSimulator sim(o, PlanarPose{3.0, 10.0, 0.0});
  Drive(&sim, {0.5, 0.0}, 10.0);
  const double d = sim.distance_driven_m();
  const Pose3 odom = sim.odometry().T_odom_base;
  // Odometry distance is 5% long, its heading turned by 0.01 rad per metre.
  EXPECT_NEAR(std::atan2(odom(1, 0), odom(0, 0)), 0.01 * d, 1e-9);
  const double odom_length = odom.translation().norm();
  EXPECT_NEAR(odom_length, 1.05 * d, 1e-3 * d);
  EXPECT_NEAR(sim.odometry().linear_velocity_mps.x(), 1.05 * 0.5, 1e-6);
  EXPECT_NEAR(sim.odometry().angular_velocity_rps.z(), 0.01 * 0.5, 1e-6);
}

TEST(ClosedLoopSimulatorTest, DefaultWheelOdometryDriftsButTracksGroundTruth) {
  SimOptions o = EmptyRoom();
  o.odometry = OdometryNoiseOptions();  // defaults: 2% scale error, bias and random drift
  const PlanarPose start{4.0, 3.0, 0.0};
  ClosedLoopSimulator sim(o, start);
  // A rounded square: straights and quarter turns.
  for (int side = 0; side < 4; ++side) {
    Drive(&sim, {0.6, 0.0}, 15.0);
    Drive(&sim, {0.3, 0.6}, 2.0 * M_PI / 4.0 / 0.6 * 1.0);
  }
  const Pose3 truth = Between(ToPose3(start), sim.T_world_base());
  const Pose3 error = Between(truth, sim.odometry().T_odom_base);
  const double d = sim.distance_driven_m();
  ASSERT_GT(d, 30.0);
  EXPECT_GT(error.translation().norm(), 0.001 * d);  // it drifts
  EXPECT_LT(error.translation().norm(), 0.08 * d);   // but a few % of the distance at most
  EXPECT_LT(RotationAngleRad(error), 0.3);
}

TEST(ClosedLoopSimulatorTest, DrivingIntoAWallCountsOneCollision) {
  const SimOptions o = EmptyRoom();
  // Facing the west wall (x = 0) 1.5 m away.
  ClosedLoopSimulator sim(o, PlanarPose{1.5, 10.0, M_PI});
  EXPECT_EQ(sim.collisions(), 0);
  EXPECT_NEAR(sim.min_clearance_m(), 1.5 - o.drive.robot_radius_m, 1e-9);
  Drive(&sim, {0.5, 0.0}, 2.0);
  EXPECT_EQ(sim.collisions(), 0);
  Drive(&sim, {0.5, 0.0}, 2.0);  // now past x = 0.3: touching
  EXPECT_EQ(sim.static_collisions().collisions, 1);
  EXPECT_LT(sim.static_collisions().min_clearance_m, 0.0);
  Drive(&sim, {0.1, 0.0}, 2.0);  // staying in contact is one event
  EXPECT_EQ(sim.collisions(), 1);
  Drive(&sim, {-0.5, 0.0}, 4.0);  // back off, then hit it again
  EXPECT_GT(sim.StaticClearanceM(), 0.0);
  EXPECT_EQ(sim.collisions(), 1);
  Drive(&sim, {0.5, 0.0}, 4.0);
  EXPECT_EQ(sim.static_collisions().collisions, 2);
  EXPECT_EQ(sim.pedestrian_collisions().collisions, 0);
  // The robot drove through the wall; rendering from outside the room is meaningless but safe.
  ASSERT_LT(sim.T_world_camera().translation().x(), 0.0);
  const SimFrame f = sim.Render();
  EXPECT_EQ(f.bgr.rows, o.intrinsics.height_px);
}

TEST(ClosedLoopSimulatorTest, DrivingIntoFurnitureCountsACollision) {
  SimOptions o = EmptyRoom();
  o.room.num_tables = 6;
  const ClosedLoopSimulator probe(o);
  // A box with free floor 1.5 m west of its edge: start there, facing it.
  std::optional<PlanarPose> start;
  for (const BoxPrimitive& box : probe.scene().boxes) {
    const PlanarPose p{box.min_m.x() - 1.5, 0.5 * (box.min_m.y() + box.max_m.y()), 0.0};
    bool free = p.x_m > 1.0;
    for (const BoxPrimitive& other : probe.scene().boxes) {
      free = free && (p.x_m < other.min_m.x() - 1.0 || p.x_m > other.max_m.x() + 1.0 ||
                      p.y_m < other.min_m.y() - 1.0 || p.y_m > other.max_m.y() + 1.0);
    }
    if (free) {
      start = p;
      break;
    }
  }
  ASSERT_TRUE(start.has_value());
  ClosedLoopSimulator sim(o, *start);
  ASSERT_GT(sim.StaticClearanceM(), 0.5);
  Drive(&sim, {0.5, 0.0}, 4.0);
  EXPECT_GE(sim.static_collisions().collisions, 1);
  EXPECT_LT(sim.min_clearance_m(), 0.0);
}

// The robot chases pedestrian 0 (walking slower than the robot) for `seconds`.
void Chase(ClosedLoopSimulator* sim, double seconds) {
  for (int i = 0; i < static_cast<int>(seconds / kDt); ++i) {
    const PedestrianState p = sim->pedestrians()[0];
    const PlanarPose& r = sim->planar_pose();
    const double bearing =
        std::remainder(std::atan2(p.y_m - r.y_m, p.x_m - r.x_m) - r.yaw_rad, 2 * M_PI);
    sim->Step({std::abs(bearing) < 0.5 ? 1.0 : 0.2, 3.0 * bearing}, kDt);
  }
}

SimOptions OneSlowWalker(double non_yielding_fraction) {
  SimOptions o = EmptyRoom();
  o.crowd.num_pedestrians = 1;
  o.crowd.speed_mps = 0.3;
  o.crowd.speed_stddev_mps = 0.0;
  o.crowd.non_yielding_fraction = non_yielding_fraction;
  o.crowd.personal_space_m = 0.1;
  return o;
}

TEST(ClosedLoopSimulatorTest, DrivingIntoANonYieldingPedestrianCountsACollision) {
  ClosedLoopSimulator sim(OneSlowWalker(1.0));
  EXPECT_EQ(sim.pedestrian_collisions().collisions, 0);
  Chase(&sim, 60.0);
  // It does not make room: the robot catching up with it touches it.
  EXPECT_GE(sim.pedestrian_collisions().collisions, 1);
  EXPECT_LT(sim.pedestrian_collisions().min_clearance_m, 0.0);
}

TEST(ClosedLoopSimulatorTest, NonYieldingPedestriansDoNotWalkIntoAStandingRobot) {
  // 40 walkers who do not give way, many crossing near the robot, which stands, then turns in
  // place: they see its body from every side and keep their personal space from it, but pass
  // much closer than yielding walkers (robot_clearance_m from base_link) would.
  SimOptions o = EmptyRoom();
  o.room.num_tables = 8;
  o.crowd.num_pedestrians = 40;
  o.crowd.crossing_fraction = 0.8;
  o.crowd.non_yielding_fraction = 1.0;
  o.crowd.personal_space_m = 0.2;
  ClosedLoopSimulator sim(o);
  Drive(&sim, {0.0, 0.0}, 40.0);
  Drive(&sim, {0.0, 0.5}, 20.0);
  EXPECT_EQ(sim.pedestrian_collisions().collisions, 0);
  EXPECT_GE(sim.pedestrian_collisions().min_clearance_m, o.crowd.personal_space_m - 1e-4);
  EXPECT_LT(sim.pedestrian_collisions().min_clearance_m, o.crowd.personal_space_m + 0.1);
  EXPECT_LT(sim.pedestrian_collisions().min_clearance_m,
            o.crowd.robot_clearance_m - o.drive.robot_radius_m);
}

TEST(ClosedLoopSimulatorTest, YieldingPedestriansKeepTheirClearance) {
  {
    ClosedLoopSimulator sim(OneSlowWalker(0.0));
    Chase(&sim, 60.0);
    EXPECT_EQ(sim.pedestrian_collisions().collisions, 0);
    const SimOptions& o = sim.options();
    EXPECT_GE(sim.pedestrian_collisions().min_clearance_m,
              o.crowd.robot_clearance_m - o.drive.robot_radius_m - 1e-4);
    // The chase got close: the walker was pushed aside, not far away.
    EXPECT_LT(sim.pedestrian_collisions().min_clearance_m,
              o.crowd.robot_clearance_m - o.drive.robot_radius_m + 0.3);
  }
  // A crowd of 40 while the robot drives around a loop.
  SimOptions o = EmptyRoom();
  o.room.num_tables = 12;
  o.crowd.num_pedestrians = 40;
  o.crowd.crossing_fraction = 0.6;
  ClosedLoopSimulator sim(o);
  for (int side = 0; side < 4; ++side) {
    Drive(&sim, {0.8, 0.0}, 6.0);
    Drive(&sim, {0.5, 1.0}, M_PI / 2.0);
  }
  EXPECT_EQ(sim.pedestrian_collisions().collisions, 0);
  EXPECT_GE(sim.pedestrian_collisions().min_clearance_m,
            o.crowd.robot_clearance_m - o.drive.robot_radius_m - 1e-4);
}

TEST(ClosedLoopSimulatorTest, SameSeedsSameStates) {
  SimOptions o = LoadSimOptions("config/sim/nav_cafeteria.yaml");
  o.intrinsics.width_px = 160;
  o.intrinsics.height_px = 120;
  o.intrinsics.fx_px = o.intrinsics.fy_px = 130.0;
  o.intrinsics.cx_px = 79.5;
  o.intrinsics.cy_px = 59.5;
  auto run = [](const SimOptions& options) {
    auto sim = std::make_unique<ClosedLoopSimulator>(options);
    for (int i = 0; i < 30; ++i) sim->Step({0.6, 0.3 * std::sin(0.2 * i)}, 0.05 + 0.005 * (i % 5));
    return sim;
  };
  const auto a = run(o), b = run(o);
  EXPECT_EQ(a->planar_pose().x_m, b->planar_pose().x_m);
  EXPECT_EQ(a->planar_pose().yaw_rad, b->planar_pose().yaw_rad);
  EXPECT_TRUE(a->odometry().T_odom_base.isApprox(b->odometry().T_odom_base, 0.0));
  ASSERT_EQ(a->num_pedestrians(), b->num_pedestrians());
  for (size_t i = 0; i < a->num_pedestrians(); ++i) {
    EXPECT_EQ(a->pedestrians()[i].x_m, b->pedestrians()[i].x_m);
    EXPECT_EQ(a->pedestrians()[i].gait_phase_rad, b->pedestrians()[i].gait_phase_rad);
  }
  const SimFrame fa = a->Render(), fb = b->Render();
  EXPECT_EQ(cv::norm(fa.bgr, fb.bgr, cv::NORM_INF), 0.0);
  EXPECT_EQ(fa.stamp, fb.stamp);

  // Another crowd seed: the same world and the same drive, other pedestrians.
  SimOptions other = o;
  other.crowd_seed = o.seed + 1;
  const auto c = run(other);
  EXPECT_EQ(a->planar_pose().x_m, c->planar_pose().x_m);
  EXPECT_EQ(a->scene().boxes.size(), c->scene().boxes.size());
  EXPECT_NE(a->pedestrians()[0].x_m, c->pedestrians()[0].x_m);
  // crowd_seed equal to seed is the default.
  SimOptions same = o;
  same.crowd_seed = o.seed;
  const auto d = run(same);
  EXPECT_EQ(a->pedestrians()[0].x_m, d->pedestrians()[0].x_m);
}

TEST(ClosedLoopSimulatorTest, RenderedFrameShowsTheGroundTruthPose) {
  SimOptions o = EmptyRoom();
  o.camera_mount.yaw_left_deg = 0.0;
  o.camera_mount.pitch_down_deg = 0.0;
  o.camera_mount.height_m = 1.0;
  ClosedLoopSimulator sim(o, PlanarPose{6.0, 9.0, 0.0});
  const RenderFlags ideal{false, false};
  const int u = o.intrinsics.width_px / 2, v = o.intrinsics.height_px / 2;
  // Facing the east wall (x = 20): the optical axis is perpendicular to it.
  SimFrame f = sim.Render(ideal);
  EXPECT_NEAR(f.depth_m.at<float>(v, u), 20.0 - 6.0 - o.camera_mount.forward_m, 1e-3);
  // Drive 2 m and turn left by 90 deg: now facing the north wall (y = 20).
  Drive(&sim, {0.5, 0.0}, 4.5);
  Drive(&sim, {0.0, 0.0}, 1.0);
  while (sim.planar_pose().yaw_rad < M_PI / 2 - 0.3) sim.Step({0.0, 0.5}, kDt);
  sim.Step({0.0, 0.0}, kDt);
  sim.Step({0.0, 0.0}, kDt);
  f = sim.Render(ideal);
  EXPECT_TRUE(f.T_world_base.isApprox(sim.T_world_base(), 1e-12));
  EXPECT_TRUE(f.T_world_camera.isApprox(sim.T_world_base() * sim.T_base_camera(), 1e-12));
  EXPECT_EQ(f.index, sim.num_steps());
  EXPECT_EQ(f.stamp, sim.stamp());
  // Ray cast of the centre pixel's ray against the room from the true camera pose.
  const Eigen::Vector3d c = f.T_world_camera.translation();
  const Eigen::Vector3d ray = f.T_world_camera.linear() *
                              Eigen::Vector3d((u - o.intrinsics.cx_px) / o.intrinsics.fx_px,
                                              (v - o.intrinsics.cy_px) / o.intrinsics.fy_px, 1.0);
  double t = std::numeric_limits<double>::infinity();
  for (int axis = 0; axis < 2; ++axis) {
    const double wall = ray[axis] > 0 ? 20.0 : 0.0;
    if (std::abs(ray[axis]) > 1e-9) t = std::min(t, (wall - c[axis]) / ray[axis]);
  }
  EXPECT_NEAR(f.depth_m.at<float>(v, u), t, 2e-3);
  EXPECT_GT(t, 5.0);
  // With sensor effects: the wall is beyond the depth range.
  f = sim.Render();
  EXPECT_TRUE(std::isnan(f.depth_m.at<float>(v, u)));
  EXPECT_EQ(cv::countNonZero(f.dynamic_mask), 0);
}

TEST(ClosedLoopSimulatorTest, RendersPedestriansInTheMask) {
  SimOptions o = LoadSimOptions("config/sim/nav_cafeteria.yaml");
  ClosedLoopSimulator sim(o);
  int masked = 0;
  for (int i = 0; i < 20; ++i) {
    sim.Step({0.5, 0.0}, 0.2);
    masked += cv::countNonZero(sim.Render().dynamic_mask);
  }
  EXPECT_GT(masked, 0);
}

TEST(ClosedLoopSimulatorTest, NavCafeteriaScenario) {
  const SimOptions o = LoadSimOptions("config/sim/nav_cafeteria.yaml");
  EXPECT_FALSE(o.handheld_camera());
  EXPECT_DOUBLE_EQ(o.camera_mount.height_m, 1.3);
  EXPECT_DOUBLE_EQ(o.camera_mount.yaw_left_deg, 0.0);
  EXPECT_GE(o.camera_mount.pitch_down_deg, 10.0);
  EXPECT_LE(o.camera_mount.pitch_down_deg, 15.0);
  EXPECT_DOUBLE_EQ(o.crowd.non_yielding_fraction, 0.3);
  EXPECT_GE(LoopRoute(o.room, o.route).length_m(), 12.0);
  const ClosedLoopSimulator sim(o);
  EXPECT_GT(sim.StaticClearanceM(), 0.5);
  EXPECT_GT(sim.PedestrianClearanceM(), 0.0);
}

TEST(ClosedLoopSimulatorTest, RejectsHandheldScenarios) {
  SimOptions o;
  o.camera_motion = sim::CameraMotion::kHandheld;
  EXPECT_THROW(ClosedLoopSimulator sim(o), LoadError);
}

TEST(PlanarScanRenderTest, RaysStopAtWallsBoxesInThePlaneAndBodyParts) {
  StaticScene scene;
  scene.room.width_m = 10.0f;
  scene.room.length_m = 8.0f;
  BoxPrimitive shelf;  // reaches the plane at 1.0 m
  shelf.min_m = Eigen::Vector3f(4.0f, 1.0f, 0.0f);
  shelf.max_m = Eigen::Vector3f(5.0f, 3.0f, 2.0f);
  BoxPrimitive table;  // below it
  table.min_m = Eigen::Vector3f(2.0f, 5.0f, 0.0f);
  table.max_m = Eigen::Vector3f(3.0f, 6.0f, 0.75f);
  scene.boxes = {shelf, table};
  CylinderPrimitive torso;
  torso.x_m = 2.0f;
  torso.y_m = 2.0f;
  torso.radius_m = 0.2f;
  torso.z_min_m = 0.8f;
  torso.z_max_m = 1.4f;
  const std::vector<CylinderPrimitive> people = {torso};
  const Eigen::Vector2d east(1, 0), west(-1, 0);
  EXPECT_NEAR(CastPlanarRay(scene, people, {1.0, 2.0}, east, 1.0), 0.8, 1e-6);   // torso
  EXPECT_NEAR(CastPlanarRay(scene, people, {1.0, 2.0}, east, 0.5), 3.0, 1e-6);   // legs' height: shelf
  EXPECT_NEAR(CastPlanarRay(scene, people, {1.0, 2.0}, west, 1.0), 1.0, 1e-6);   // west wall
  EXPECT_NEAR(CastPlanarRay(scene, people, {1.0, 5.5}, east, 1.0), 9.0, 1e-6);   // over the table
  EXPECT_NEAR(CastPlanarRay(scene, people, {1.0, 5.5}, east, 0.5), 1.0, 1e-6);   // the table
  EXPECT_NEAR(CastPlanarRay(scene, people, {4.5, 4.0}, Eigen::Vector2d(0, -1), 1.0), 1.0, 1e-6);

  // A scan from (1, 2) heading north: 360 beams, beam 0 at -180 deg (south), beam 90 east.
  ScannerOptions o;
  o.beams = 360;
  o.range_noise_m = 0.0;
  o.max_range_m = 5.0;
  Rng rng(1);
  const PlanarScan scan =
      RenderPlanarScan(o, scene, people, PlanarPose{1.0, 2.0, M_PI / 2}, Time(), rng);
  ASSERT_EQ(scan.ranges_m.size(), 360u);
  EXPECT_NEAR(scan.angle_min_rad, -M_PI, 1e-12);
  EXPECT_NEAR(scan.angle_increment_rad, M_PI / 180.0, 1e-12);
  EXPECT_NEAR(scan.ranges_m[90], 0.8, 1e-5);   // east: the torso
  EXPECT_NEAR(scan.ranges_m[0], 2.0, 1e-5);    // south wall
  EXPECT_NEAR(scan.ranges_m[270], 1.0, 1e-5);  // west wall
  EXPECT_TRUE(std::isinf(scan.ranges_m[180]));  // north: the wall 6 m off, beyond range
}

TEST(PlanarScanRenderTest, TheClosedLoopRobotSeesTheWalkerNearestToIt) {
  SimOptions o = LoadSimOptions("config/sim/nav_cafeteria.yaml");
  o.scanner.enabled = true;
  ClosedLoopSimulator sim(o);
  Drive(&sim, {0.3, 0.0}, 3.0);
  const PlanarScan a = sim.RenderScan();
  const PlanarScan b = sim.RenderScan();
  EXPECT_EQ(a.ranges_m, b.ranges_m);  // a function of the state
  const std::vector<PedestrianState> people = sim.pedestrians();
  ASSERT_FALSE(people.empty());
  const Eigen::Vector2d base(sim.planar_pose().x_m, sim.planar_pose().y_m);
  size_t nearest = 0;
  for (size_t i = 1; i < people.size(); ++i) {
    if ((Eigen::Vector2d(people[i].x_m, people[i].y_m) - base).norm() <
        (Eigen::Vector2d(people[nearest].x_m, people[nearest].y_m) - base).norm()) {
      nearest = i;
    }
  }
  const Eigen::Vector2d walker(people[nearest].x_m, people[nearest].y_m);
  ASSERT_LT((walker - base).norm(), o.scanner.max_range_m);
  const Pose3 T_world_scanner = sim.T_world_base() * sim.T_base_scanner();
  int on_walker = 0;
  for (const Eigen::Vector3d& p : ScanPointsInBase(a, Pose3::Identity())) {
    const Eigen::Vector3d w = T_world_scanner * p;
    on_walker += (w.head<2>() - walker).norm() < 0.4 ? 1 : 0;
  }
  EXPECT_GE(on_walker, 3) << "walker " << (walker - base).norm() << " m off";
}

}  // namespace
}  // namespace icgm::sim
