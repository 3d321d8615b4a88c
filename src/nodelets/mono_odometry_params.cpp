#include "nodelets/mono_odometry_params.h"

#include "nodelets/nodelet_params.h"

namespace icgm::nodelets {

MonoOdometryParams ReadMonoOdometryParams(const ros::NodeHandle& pnh) {
  MonoOdometryParams p;
  const std::string config_file = Param(pnh, "config_file", "");
  if (!config_file.empty()) p.options = LoadMonoOptions(config_file);
  bool use_icgm = p.options.vo.use_icgm;
  if (GetParam(pnh, "use_icgm", &use_icgm)) p.options.vo.use_icgm = use_icgm;
  ParamInto(pnh, "odom_frame", &p.msg.odom_frame);
  ParamInto(pnh, "child_frame", &p.msg.child_frame);
  ParamInto(pnh, "sigma_position_m", &p.msg.sigma_position_m);
  ParamInto(pnh, "sigma_rotation_rad", &p.msg.sigma_rotation_rad);
  ParamInto(pnh, "publish_tf", &p.publish_tf);
  ParamInto(pnh, "queue_size", &p.queue_size);
  ParamInto(pnh, "camera_info_wait_s", &p.camera_info_wait_s);
  ParamInto(pnh, "wheel_odometry", &p.wheel_odometry);
  ParamInto(pnh, "max_wait_frames", &p.max_wait_frames);
  ParamInto(pnh, "base_frame", &p.base_frame);
  return p;
}

}  // namespace icgm::nodelets
