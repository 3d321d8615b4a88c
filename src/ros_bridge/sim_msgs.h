// The closed-loop simulator (core/sim/closed_loop_simulator.h) -> ROS messages: its ground-truth
// status (pose, collisions, clearances) and the walkers' positions. Tests in
// test/ros_bridge/sim_msgs_test.cpp.
#pragma once

#include <string>
#include <vector>

#include <geometry_msgs/PoseArray.h>
#include <icgm_slam/SimStatus.h>

#include "core/common/time.h"
#include "core/sim/closed_loop_simulator.h"

namespace icgm::ros_bridge {

icgm_slam::SimStatus ToSimStatusMsg(const sim::ClosedLoopSimulator& sim,
                                    const std::string& world_frame);

// One pose per walker on the floor (z = 0), heading its walking direction.
geometry_msgs::PoseArray ToPeopleMsg(const std::vector<sim::PedestrianState>& people,
                                     const std::string& frame_id, Time stamp);
// Floor positions and headings back (gait and swing are not carried).
std::vector<sim::PedestrianState> FromPeopleMsg(const geometry_msgs::PoseArray& msg);

}  // namespace icgm::ros_bridge
