// Rolling shutter: a CMOS sensor (the Kinect v1 colour camera among them) exposes its rows one
// after another, so a moving camera sees every row from a slightly different pose. With the
// camera's velocity over the frame (constant body twist), each row's capture pose is known
// relative to the frame's stamp instant, and keypoints and depth can be carried to that one
// instant ("de-skewed"): registration and the map then see a frame as a global-shutter camera at
// its stamp would have.
//
// Convention: T(t + s) = T(t) * Exp(s * twist) for the camera pose T and a body twist in the
// camera frame per second (pose.h's (translation, rotation vector) order). Row v is captured
// first_row_s + v * line_s after the stamp.
#pragma once

#include <vector>

#include <opencv2/core.hpp>

#include "core/common/camera.h"
#include "core/common/pose.h"

namespace icgm {

struct RowTiming {
  // Capture instant of row 0 minus the frame's stamp (s).
  double first_row_s = 0.0;
  // Time between the capture of consecutive rows (s); 0 for a global shutter.
  double line_s = 0.0;
  double RowOffsetS(double row) const { return first_row_s + row * line_s; }
};

// stamp_from_row[v]: p_stamp = stamp_from_row[v] * p_row for a point seen in row v, the camera
// moving with `twist_per_s`; `rows` entries.
std::vector<Pose3> StampFromRowPoses(int rows, const RowTiming& timing,
                                     const Vec6& twist_per_s);

// Moves each keypoint to where the camera at the stamp instant sees its point. The point's depth
// is read from `depth_stamp_m` (CV_32FC1 metres at the stamp instant) at the keypoint; without
// depth there, the keypoint moves as a point at infinity (rotation only). Keypoints outside the
// image stay where they are.
void DeskewKeypoints(const std::vector<Pose3>& stamp_from_row, const cv::Mat& depth_stamp_m,
                     const CameraIntrinsics& intrinsics, std::vector<cv::KeyPoint>* keypoints);

}  // namespace icgm
