#include "core/sensor/robot_options.h"

namespace icgm {

namespace {
void ReadName(const OptionReader& r, const std::string& key, std::string* value) {
  r.Read(key, value);
  if (value->empty()) throw LoadError(r.path() + "." + key + ": must not be empty");
}
}  // namespace

void ReadOptions(const OptionReader& r, RobotOptions* o) {
  ReadName(r, "name", &o->name);
  ReadName(r, "base_frame", &o->base_frame);
  ReadName(r, "camera_frame", &o->camera_frame);
  r.Read("camera_x_m", &o->camera_x_m, -10.0, 10.0);
  r.Read("camera_y_m", &o->camera_y_m, -10.0, 10.0);
  r.Read("camera_z_m", &o->camera_z_m, -10.0, 10.0);
  r.Read("camera_roll_deg", &o->camera_roll_deg, -180.0, 180.0);
  r.Read("camera_pitch_deg", &o->camera_pitch_deg, -180.0, 180.0);
  r.Read("camera_yaw_deg", &o->camera_yaw_deg, -180.0, 180.0);
  ReadName(r, "wheel_odom_topic", &o->wheel_odom_topic);
  ReadName(r, "cmd_vel_topic", &o->cmd_vel_topic);
  r.Read("max_linear_mps", &o->max_linear_mps, 1e-3, 5.0);
  r.Read("max_angular_dps", &o->max_angular_dps, 1e-3, 720.0);
}

RobotOptions LoadRobotOptions(const std::string& yaml_path) {
  const OptionReader root = OptionReader::FromFile(yaml_path);
  if (!root.Has("robot")) throw LoadError(yaml_path + ": no 'robot' section");
  const OptionReader section = root.Section("robot");
  RobotOptions options;
  ReadOptions(section, &options);
  OptionReader::RejectUnknownKeys({&root, &section});
  return options;
}

}  // namespace icgm
