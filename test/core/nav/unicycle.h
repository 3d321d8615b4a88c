// Test helper: exact unicycle kinematics for closed-loop tests of the controller and navigator.
#pragma once

#include <cmath>

#include "core/common/velocity_command.h"
#include "core/nav/planar_pose.h"

namespace icgm::test {

inline Pose2D Drive(const Pose2D& p, const VelocityCommand& c, double dt) {
  Pose2D q = p;
  const double mid = p.yaw_rad + 0.5 * c.angular_radps * dt;
  q.x_m += c.linear_mps * dt * std::cos(mid);
  q.y_m += c.linear_mps * dt * std::sin(mid);
  q.yaw_rad = WrapAngleRad(p.yaw_rad + c.angular_radps * dt);
  return q;
}

}  // namespace icgm::test
