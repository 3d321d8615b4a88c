#include "nodelets/mono_odometry_params.h"

namespace icgm::nodelets {

MonoOdometryParams ReadMonoOdometryParams(const ros::NodeHandle& pnh) {
  MonoOdometryParams p;
  std::string config_file;
  pnh.param<std::string>("config_file", config_file, "");
  if (!config_file.empty()) p.options = LoadMonoOptions(config_file);
  bool use_icgm = p.options.vo.use_icgm;
  if (pnh.getParam("use_icgm", use_icgm)) p.options.vo.use_icgm = use_icgm;
  pnh.param<std::string>("odom_frame", p.msg.odom_frame, p.msg.odom_frame);
  pnh.param<std::string>("child_frame", p.msg.child_frame, p.msg.child_frame);
  pnh.param("sigma_position_m", p.msg.sigma_position_m, p.msg.sigma_position_m);
  pnh.param("sigma_rotation_rad", p.msg.sigma_rotation_rad, p.msg.sigma_rotation_rad);
  pnh.param("publish_tf", p.publish_tf, p.publish_tf);
  pnh.param("queue_size", p.queue_size, p.queue_size);
  pnh.param("camera_info_wait_s", p.camera_info_wait_s, p.camera_info_wait_s);
  pnh.param("wheel_odometry", p.wheel_odometry, p.wheel_odometry);
  pnh.param("max_wait_frames", p.max_wait_frames, p.max_wait_frames);
  pnh.param<std::string>("base_frame", p.base_frame, p.base_frame);
  return p;
}

}  // namespace icgm::nodelets
