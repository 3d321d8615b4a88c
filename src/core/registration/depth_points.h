// Lifts 2-D keypoints to 3-D camera-frame points using a registered metric depth image
// (CV_32FC1 metres, NaN or 0 = no measurement), as needed to build the thesis's metric model
// M_t (ch. 6.1.1.1): "a set of robust vision features and their corresponding 3D coordinates".
//
// A keypoint is dropped, with the reason counted, when its depth is missing (NaN/0), outside
// [min_depth_m, max_depth_m], or lies on a depth discontinuity (an object border, where the
// depth of a corner feature is ambiguous between foreground and background). The discontinuity
// test compares the centre depth with its 3x3 neighbourhood: a neighbour that differs by more
// than max_depth_jump_ratio * z (or is missing) marks the pixel as unreliable.
#pragma once

#include <cstddef>
#include <string>
#include <vector>

#include <Eigen/Core>
#include <opencv2/core.hpp>

#include "core/common/camera.h"

namespace icgm {

struct DepthPointOptions {
  double min_depth_m = 0.3;
  double max_depth_m = 6.0;
  // A 3x3 neighbour whose depth differs from the centre by more than this fraction of the centre
  // depth makes the keypoint a discontinuity. <= 0 disables the test.
  double max_depth_jump_ratio = 0.05;
};

// Why keypoints were dropped; counted per registration.
struct DepthRejectCounts {
  size_t outside_image = 0;  // keypoint not inside the depth image
  size_t missing = 0;        // NaN / zero depth
  size_t out_of_range = 0;   // depth outside [min_depth_m, max_depth_m]
  size_t discontinuity = 0;  // depth jump in the 3x3 neighbourhood

  size_t total() const { return outside_image + missing + out_of_range + discontinuity; }
  DepthRejectCounts& operator+=(const DepthRejectCounts& o);
  // "missing 12, out of range 3, discontinuity 5, outside image 0".
  std::string ToString() const;
};

enum class DepthLookup { kOk, kOutsideImage, kMissing, kOutOfRange, kDiscontinuity };

// Depth at the pixel nearest to `px`; on kOk writes it to *z_m. `depth_m` must be CV_32FC1.
DepthLookup LookupDepth(const cv::Mat& depth_m, const cv::Point2f& px,
                        const DepthPointOptions& options, double* z_m);

// Adds one to the counter matching a non-kOk lookup result.
void CountReject(DepthLookup result, DepthRejectCounts* counts);

// The depth image scaled by the camera's calibrated correction (CameraIntrinsics::
// depth_correction); `depth_m` itself when the correction is 1 or it is not CV_32FC1.
cv::Mat CorrectedDepth(const cv::Mat& depth_m, const CameraIntrinsics& intrinsics);

// Back-projects every keypoint; points[i] is valid iff valid[i] != 0 (then the camera-frame
// point, x right, y down, z forward). Counts the rejects when `counts` is given.
void KeypointsToPoints(const std::vector<cv::Point2f>& pixels, const cv::Mat& depth_m,
                       const CameraIntrinsics& intrinsics, const DepthPointOptions& options,
                       std::vector<Eigen::Vector3d>* points, std::vector<uint8_t>* valid,
                       DepthRejectCounts* counts = nullptr);

}  // namespace icgm
