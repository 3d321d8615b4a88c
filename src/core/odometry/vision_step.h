// What the odometry fusion is given for a front-end frame: the front end's motion since the
// previous frame when vision measured it (status ok, relative_pose = T_prev_cur); otherwise the
// registration with a failed status and its reason, so the fusion redoes the wheel and
// constant-velocity fallbacks with its own wheel data.
#pragma once

#include "core/common/pose.h"
#include "core/odometry/frontend_types.h"

namespace icgm {

RegistrationResult VisionStep(const FrontendFrameResult& frame, const Pose3& previous_odom_camera);

}  // namespace icgm
