// A robot's description for the launch files and the tools (config/robot/*.yaml, section
// `robot:`): where the RGB-D camera sits on the base, the base's wheel-odometry and velocity
// command topics and its speed limits. The camera mount is base_link -> camera_link (the
// camera's body frame, x forward, z up); the URDF (description/*.urdf) carries the same values,
// and the optical frame below camera_link follows the usual openni convention.
#pragma once

#include <string>

#include "core/common/option_reader.h"

namespace icgm {

struct RobotOptions {
  std::string name = "robot";
  std::string base_frame = "base_link";
  std::string camera_frame = "camera_link";
  double camera_x_m = 0.0;
  double camera_y_m = 0.0;
  double camera_z_m = 0.0;
  double camera_roll_deg = 0.0;
  double camera_pitch_deg = 0.0;
  double camera_yaw_deg = 0.0;
  std::string wheel_odom_topic = "/odom";
  std::string cmd_vel_topic = "/cmd_vel";
  double max_linear_mps = 0.5;
  double max_angular_dps = 45.0;
};

// Reads the `robot` section; throws LoadError for a wrong type or out-of-range value (mount
// within +-10 m and +-180 deg, speeds in (0, 5] m/s and (0, 720] deg/s, non-empty names).
void ReadOptions(const OptionReader& robot_section, RobotOptions* options);

// Reads the `robot` section of a file, rejecting unknown keys there and at the top level.
RobotOptions LoadRobotOptions(const std::string& yaml_path);

}  // namespace icgm
