// A frame brought to its colour stamp's instant: the depth image captured at another instant
// (Kinect v1: colour and depth unsynchronized) and the rows of a rolling shutter, both carried
// with the camera's velocity (constant body twist, pose.h order, per second). The RGB-D front end
// and the map builder's keyframes use the same steps.
#pragma once

#include <optional>
#include <vector>

#include <opencv2/core.hpp>

#include "core/common/camera.h"
#include "core/common/pose.h"
#include "core/common/time.h"
#include "core/registration/rolling_shutter.h"

namespace icgm {

// Camera velocity from t0 to t1 (poses T_odom_camera); none when the two are not 0 < gap <=
// max_gap_s apart or the motion is not finite.
std::optional<Vec6> VelocityTwist(Time t0, const Pose3& odom_camera_t0, Time t1,
                                  const Pose3& odom_camera_t1, double max_gap_s);

// Capture instant of the depth minus that of the colour image (s): the stamps' difference plus
// the camera's depth_time_offset_s; 0 below min_s.
double DepthTimeOffsetS(Time colour_stamp, Time depth_stamp, const CameraIntrinsics& intrinsics,
                        double min_s);

// The camera's rolling shutter: true when its readout or first-row offset is not zero.
bool HasRollingShutter(const CameraIntrinsics& intrinsics);
RowTiming ColourRowTiming(const CameraIntrinsics& intrinsics);

// `depth_m` (CV_32FC1 metres, captured depth_dt_s after the colour stamp, rows with the camera's
// row timing) re-rendered at the colour stamp's instant; `depth_m` itself when there is nothing
// to bridge (no time difference, global shutter).
cv::Mat DepthAtStamp(const cv::Mat& depth_m, const CameraIntrinsics& intrinsics,
                     double depth_dt_s, const Vec6& twist);

// Keypoints of a rolling-shutter colour image carried to the stamp's instant with the depth at
// that instant (DeskewKeypoints); unchanged for a global shutter.
void KeypointsAtStamp(const CameraIntrinsics& intrinsics, const Vec6& twist,
                      const cv::Mat& depth_at_stamp_m, std::vector<cv::KeyPoint>* keypoints);

}  // namespace icgm
