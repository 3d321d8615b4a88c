#include "core/odometry/vision_step.h"

#include "core/odometry/odometry_fusion.h"

namespace icgm {

RegistrationResult VisionStep(const FrontendFrameResult& frame,
                              const Pose3& previous_odom_camera) {
  RegistrationResult result = frame.registration;
  if (frame.source == MotionSource::kVision) {
    result.status = Status::Ok();
    result.relative_pose = Between(previous_odom_camera, frame.odom_camera);
  } else if (result.status.ok()) {
    result.status = Status::Error("no vision motion for this frame");
  }
  return result;
}

std::optional<VisionStepChain::Step> VisionStepChain::Add(const FrontendFrameResult& frame) {
  std::optional<Step> step;
  if (previous_stamp_) {
    step = Step{VisionStep(frame, previous_odom_camera_), frame.stamp, *previous_stamp_};
  }
  previous_stamp_ = frame.stamp;
  previous_odom_camera_ = frame.odom_camera;
  return step;
}

}  // namespace icgm
