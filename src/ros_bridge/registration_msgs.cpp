#include "ros_bridge/registration_msgs.h"

#include "ros_bridge/conversions.h"

namespace icgm::ros_bridge {

icgm_slam::RegistrationResult ToRegistrationMsg(const RegistrationResult& r, Time stamp,
                                                Time reference_stamp,
                                                const std::string& frame_id) {
  icgm_slam::RegistrationResult m;
  m.header.stamp = ToRos(stamp);
  m.header.frame_id = frame_id;
  m.reference_stamp = ToRos(reference_stamp);
  m.relative_pose = ToPoseMsg(r.relative_pose);
  for (int i = 0; i < 6; ++i) {
    for (int j = 0; j < 6; ++j) m.covariance[6 * i + j] = r.covariance(i, j);
  }
  m.success = r.status.ok();
  m.reason = r.status.ok() ? std::string() : r.status.reason();
  m.matches_2d = static_cast<uint32_t>(r.matches_2d);
  m.matches_3d = static_cast<uint32_t>(r.matches_3d);
  m.inliers = static_cast<uint32_t>(r.inliers);
  m.inlier_ratio = static_cast<float>(r.inlier_ratio);
  m.rmse_m = static_cast<float>(r.rmse_m);
  return m;
}

RegistrationResult FromRegistrationMsg(const icgm_slam::RegistrationResult& m) {
  RegistrationResult r;
  r.status = m.success ? Status::Ok()
                       : Status::Error(m.reason.empty() ? "registration failed" : m.reason);
  r.relative_pose = FromPoseMsg(m.relative_pose);
  for (int i = 0; i < 6; ++i) {
    for (int j = 0; j < 6; ++j) r.covariance(i, j) = m.covariance[6 * i + j];
  }
  r.matches_2d = m.matches_2d;
  r.matches_3d = m.matches_3d;
  r.inliers = m.inliers;
  r.inlier_ratio = m.inlier_ratio;
  r.rmse_m = m.rmse_m;
  return r;
}

}  // namespace icgm::ros_bridge
