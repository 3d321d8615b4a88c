#include "ros_bridge/sim_msgs.h"

#include <cmath>

#include <gtest/gtest.h>

#include "ros_bridge/conversions.h"

namespace icgm::ros_bridge {
namespace {

sim::SimOptions SmallRoom() {
  sim::SimOptions o;
  o.seed = 5;
  o.room.width_m = 8.0;
  o.room.length_m = 8.0;
  o.room.num_tables = 2;
  o.room.num_shelves = 1;
  o.room.num_pillars = 0;
  o.crowd.num_pedestrians = 3;
  return o;
}

TEST(SimMsgsTest, StatusCarriesTheSimulatorsGroundTruth) {
  sim::ClosedLoopSimulator sim(SmallRoom());
  VelocityCommand cmd;
  cmd.linear_mps = 0.4;
  cmd.angular_radps = 0.2;
  for (int i = 0; i < 20; ++i) sim.Step(cmd, 0.05);
  const icgm_slam::SimStatus m = ToSimStatusMsg(sim, "world");
  EXPECT_EQ(m.header.frame_id, "world");
  EXPECT_EQ(FromRos(m.header.stamp), sim.stamp());
  EXPECT_TRUE(FromPoseMsg(m.base_pose).isApprox(sim.T_world_base(), 1e-12));
  EXPECT_GT(m.distance_driven_m, 0.1);  // it moved
  EXPECT_DOUBLE_EQ(m.distance_driven_m, sim.distance_driven_m());
  EXPECT_DOUBLE_EQ(m.linear_mps, sim.true_velocity().linear_mps);
  EXPECT_DOUBLE_EQ(m.angular_radps, sim.true_velocity().angular_radps);
  EXPECT_EQ(m.static_collisions, sim.static_collisions().collisions);
  EXPECT_EQ(m.pedestrian_collisions, sim.pedestrian_collisions().collisions);
  EXPECT_DOUBLE_EQ(m.static_clearance_m, sim.StaticClearanceM());
  EXPECT_DOUBLE_EQ(m.pedestrian_clearance_m, sim.PedestrianClearanceM());
  EXPECT_DOUBLE_EQ(m.min_static_clearance_m, sim.static_collisions().min_clearance_m);
  EXPECT_EQ(m.num_pedestrians, 3);
}

TEST(SimMsgsTest, PeopleRoundTripKeepsPositionAndHeading) {
  std::vector<sim::PedestrianState> people(3);
  const float headings[3] = {0.0f, 2.5f, -3.0f};
  for (int i = 0; i < 3; ++i) {
    people[i].x_m = 1.0f + i;
    people[i].y_m = -0.5f * i;
    people[i].heading_rad = headings[i];
    people[i].gait_phase_rad = 1.0f;
  }
  const geometry_msgs::PoseArray msg = ToPeopleMsg(people, "world", Time::FromSeconds(7));
  EXPECT_EQ(msg.header.frame_id, "world");
  ASSERT_EQ(msg.poses.size(), 3u);
  EXPECT_EQ(msg.poses[1].position.z, 0.0);
  const auto back = FromPeopleMsg(msg);
  ASSERT_EQ(back.size(), 3u);
  for (int i = 0; i < 3; ++i) {
    EXPECT_FLOAT_EQ(back[i].x_m, people[i].x_m);
    EXPECT_FLOAT_EQ(back[i].y_m, people[i].y_m);
    EXPECT_NEAR(std::remainder(back[i].heading_rad - people[i].heading_rad, 2 * M_PI), 0.0, 1e-5);
  }
  EXPECT_TRUE(FromPeopleMsg(ToPeopleMsg({}, "world", Time())).empty());
}

}  // namespace
}  // namespace icgm::ros_bridge
