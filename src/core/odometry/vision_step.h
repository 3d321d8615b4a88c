// What the odometry fusion is given for a front-end frame: the front end's motion since the
// previous frame when vision measured it (status ok, relative_pose = T_prev_cur); otherwise the
// registration with a failed status and its reason, so the fusion redoes the wheel and
// constant-velocity fallbacks with its own wheel data.
#pragma once

#include <optional>

#include "core/common/pose.h"
#include "core/common/time.h"
#include "core/odometry/frontend_types.h"

namespace icgm {

RegistrationResult VisionStep(const FrontendFrameResult& frame, const Pose3& previous_odom_camera);

// The steps between consecutive processed frames (frames the front end dropped do not count):
// the first frame gives none, every later one its VisionStep from the one before.
class VisionStepChain {
 public:
  struct Step {
    RegistrationResult result;
    Time stamp;
    Time reference_stamp;  // the previous frame's
  };
  std::optional<Step> Add(const FrontendFrameResult& frame);

 private:
  std::optional<Time> previous_stamp_;
  Pose3 previous_odom_camera_ = Pose3::Identity();
};

}  // namespace icgm
