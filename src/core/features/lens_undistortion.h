// Lens distortion of a camera undone (CameraIntrinsics' k1 k2 p1 p2 k3, OpenCV / ROS plumb_bob):
// images resampled to the ideal pinhole camera with the same fx, fy, cx, cy; keypoints found on
// a raw image moved there. The RGB-D front end and the feature extraction nodelet share it, so
// features come from the same undistorted image offline and live.
#pragma once

#include <vector>

#include <opencv2/core.hpp>

#include "core/common/camera.h"

namespace icgm {

class LensUndistortion {
 public:
  LensUndistortion() = default;  // inactive: every call returns its input
  explicit LensUndistortion(const CameraIntrinsics& camera);

  // False for a camera without distortion.
  bool active() const { return !map_x_.empty(); }

  // A new image (the input is never written); the input itself when inactive, empty, or of
  // another size than the camera's. Colour and grey: bilinear.
  cv::Mat Colour(const cv::Mat& raw) const;
  // CV_32FC1 depth (metres): nearest neighbour, so no depth mixes across an edge; pixels that
  // fall outside the raw image become NaN. Other types are returned as they are.
  cv::Mat Depth(const cv::Mat& raw_m) const;
  // Keypoints detected on the raw image, moved to the ideal image.
  void MoveKeypoints(std::vector<cv::KeyPoint>* keypoints) const;

 private:
  bool Fits(const cv::Mat& image) const;

  cv::Matx33d k_ = cv::Matx33d::eye();
  cv::Vec<double, 5> d_;
  cv::Mat map_x_, map_y_;  // ideal pixel -> raw pixel
};

}  // namespace icgm
