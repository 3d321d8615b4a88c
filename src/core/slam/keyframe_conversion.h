// Front-end keyframe -> metric model M_n of the hybrid map (thesis 6.1.1.1: "a set of robust
// vision features and these features' corresponding 3D coordinates, called a metric model").
//  - features: only the keypoints whose match survived ICGM (FrontendKeyframe::robust) and that
//    have a valid 3D point; a keyframe the front end had no reference for (the first one, flags
//    all zero) keeps every keypoint with a 3D point when keep_all_without_reference is set;
//  - relative pose R_n (eq. 6.1): this keyframe in the previous *map* keyframe's camera frame,
//    from the two odometry poses T_odom_camera (a front-end keyframe the map did not take is
//    skipped, so R_n still chains consecutive map keyframes);
//  - RelativePoseSource from the front end's MotionSource of the keyframe's last step.
#pragma once

#include <optional>

#include "core/common/pose.h"
#include "core/map/keyframe.h"
#include "core/odometry/frontend_types.h"

namespace icgm {

struct KeyframeConversionOptions {
  // A keyframe without any ICGM flag (no reference yet) keeps all keypoints with depth.
  bool keep_all_without_reference = true;
  // false: every keypoint with a 3-D point is kept, ICGM flag or not (comparison runs).
  bool robust_only = true;
};

// Vision -> kVisual; wheel odometry, constant velocity or no motion -> kWheelOdometry (a
// non-visual step: the map gives its link the weaker odometry information).
RelativePoseSource ToRelativePoseSource(MotionSource source);

// `previous_odom_camera`: T_odom_camera of the previous map keyframe of the same session, or
// nullopt for the first one; R_n is then `session_from_odom` * T_odom_camera, i.e. the
// keyframe's pose in the session's world frame (identity: the session starts at the odometry
// origin). The returned keyframe has no ids or global pose (HybridMap assigns them).
Keyframe ToMapKeyframe(const FrontendKeyframe& keyframe,
                       const std::optional<Pose3>& previous_odom_camera,
                       const Pose3& session_from_odom = Pose3::Identity(),
                       const KeyframeConversionOptions& options = KeyframeConversionOptions());

}  // namespace icgm
