// A metric model M_n of the hybrid map (thesis 6.1.1.1): the ICGM-robust features of one RGB-D
// frame with their 3D coordinates, its relative pose R_n and global pose L_n (eq. 6.1).
#pragma once

#include <cstdint>
#include <vector>

#include <Eigen/Core>
#include <opencv2/core.hpp>

#include "core/common/pose.h"
#include "core/common/time.h"
#include "core/map/keyframe_images.h"

namespace icgm {

// Where R_n came from: 6D registration of RGB-D frames, or wheel odometry when that failed
// (thesis 6.1.1.1 keeps the topology with tire odometry).
enum class RelativePoseSource : int { kSessionStart = 0, kVisual = 1, kWheelOdometry = 2 };

struct Keyframe {
  int id = -1;           // dense map index, assigned by HybridMap
  int session_id = -1;   // assigned by HybridMap
  int loop_id = -1;      // traversal ("learned loop") this model belongs to; assigned by HybridMap
  int previous_id = -1;  // previous keyframe of the same session (-1: first of the session)
  Time stamp;
  std::vector<cv::KeyPoint> keypoints;  // ICGM-robust features only
  cv::Mat descriptors;                  // one row per keypoint, CV_8U (binary) or CV_32F
  // Camera-frame 3D point of each keypoint in metres; NaN where depth was missing.
  std::vector<Eigen::Vector3d> points_m;
  // Dictionary word of each descriptor row as assigned when the keyframe entered the map's
  // dictionary (empty: unknown). Saved with the map so loading replays the dictionary instead
  // of searching it again (VisualDictionary::AddAssigned).
  std::vector<int32_t> word_ids;
  // R_n: this keyframe in the previous keyframe's frame (in the session origin for the first).
  Pose3 relative_pose = Pose3::Identity();
  RelativePoseSource relative_source = RelativePoseSource::kVisual;
  Pose3 global_pose = Pose3::Identity();  // L_n, maintained by HybridMap
  // Downsampled depth and colour of the frame (empty unless the map stores them).
  KeyframeImages images;

  bool binary() const { return descriptors.depth() == CV_8U; }
};

}  // namespace icgm
