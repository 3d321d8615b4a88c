#include "ros_bridge/sim_msgs.h"

#include <cmath>

#include "ros_bridge/conversions.h"

namespace icgm::ros_bridge {

icgm_slam::SimStatus ToSimStatusMsg(const sim::ClosedLoopSimulator& sim,
                                    const std::string& world_frame) {
  icgm_slam::SimStatus m;
  m.header.frame_id = world_frame;
  m.header.stamp = ToRos(sim.stamp());
  m.base_pose = ToPoseMsg(sim.T_world_base());
  m.distance_driven_m = sim.distance_driven_m();
  m.linear_mps = sim.true_velocity().linear_mps;
  m.angular_radps = sim.true_velocity().angular_radps;
  m.static_collisions = sim.static_collisions().collisions;
  m.pedestrian_collisions = sim.pedestrian_collisions().collisions;
  m.static_clearance_m = sim.StaticClearanceM();
  m.pedestrian_clearance_m = sim.PedestrianClearanceM();
  m.min_static_clearance_m = sim.static_collisions().min_clearance_m;
  m.min_pedestrian_clearance_m = sim.pedestrian_collisions().min_clearance_m;
  m.num_pedestrians = static_cast<int>(sim.num_pedestrians());
  return m;
}

geometry_msgs::PoseArray ToPeopleMsg(const std::vector<sim::PedestrianState>& people,
                                     const std::string& frame_id, Time stamp) {
  geometry_msgs::PoseArray m;
  m.header.frame_id = frame_id;
  m.header.stamp = ToRos(stamp);
  m.poses.resize(people.size());
  for (size_t i = 0; i < people.size(); ++i) {
    m.poses[i].position.x = people[i].x_m;
    m.poses[i].position.y = people[i].y_m;
    m.poses[i].orientation.z = std::sin(people[i].heading_rad / 2);
    m.poses[i].orientation.w = std::cos(people[i].heading_rad / 2);
  }
  return m;
}

std::vector<sim::PedestrianState> FromPeopleMsg(const geometry_msgs::PoseArray& msg) {
  std::vector<sim::PedestrianState> people(msg.poses.size());
  for (size_t i = 0; i < msg.poses.size(); ++i) {
    const auto& p = msg.poses[i];
    people[i].x_m = static_cast<float>(p.position.x);
    people[i].y_m = static_cast<float>(p.position.y);
    // Yaw of a rotation about z (as written above; any other rotation is projected on it).
    people[i].heading_rad = static_cast<float>(std::atan2(
        2.0 * (p.orientation.w * p.orientation.z + p.orientation.x * p.orientation.y),
        1.0 - 2.0 * (p.orientation.y * p.orientation.y + p.orientation.z * p.orientation.z)));
  }
  return people;
}

}  // namespace icgm::ros_bridge
