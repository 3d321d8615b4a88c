// Keyframe selection for the distributed pipeline: the map-building nodelet receives each
// frame's robust features (from the feature extraction nodelet), its registered depth and the
// fused odometry pose, and makes a metric model (FrontendKeyframe) when the camera has moved
// enough since the last one — the same kind of keyframe the offline RgbdFrontend hands to the
// map (thesis ch. 6.1.1.1: a metric model is the robust features with their 3D coordinates).
#pragma once

#include <optional>
#include <utility>

#include <opencv2/core.hpp>

#include "core/common/camera.h"
#include "core/common/pose.h"
#include "core/icgm/robust_feature_tracker.h"
#include "core/odometry/frontend_types.h"

namespace icgm {

class OptionReader;

struct KeyframerOptions {
  double min_translation_m = 0.25;  // new keyframe after this much camera translation...
  double min_rotation_deg = 15.0;   // ...or rotation since the last keyframe...
  int max_interval_frames = 30;     // ...or this many frames
  int min_robust_points = 20;       // frames with fewer robust 3D points are not keyframes
  DepthPointOptions depth;
  // A keyframe brought to its colour stamp's instant as the offline front end does it
  // (core/registration/sensor_timing.h): depth captured at another instant (depth stamp plus
  // the camera's depth_time_offset_s) and a rolling shutter's rows, with the camera velocity
  // between the previous offered frame and this one, when they are at most
  // max_velocity_gap_s apart.
  bool compensate_sensor_timing = true;
  double max_velocity_gap_s = 0.1;
  double depth_timing_min_s = 0.001;  // smaller depth-colour time differences are ignored
};

// Fills `options` from a `keyframer:` section; throws LoadError on bad values.
void ReadOptions(const OptionReader& reader, KeyframerOptions* options);

class ObservationKeyframer {
 public:
  explicit ObservationKeyframer(const KeyframerOptions& options) : options_(options) {}

  // Offers one frame with its odometry pose T_odom_camera. Returns the keyframe when this frame
  // becomes one (always the first acceptable frame). `source` says where the motion since the
  // previous frame came from (kVision unless known otherwise). `depth_stamp`: when the depth
  // image was stamped (default: with the colour image).
  std::optional<FrontendKeyframe> Offer(const TrackedFrame& frame, const cv::Mat& depth_m,
                                        const CameraIntrinsics& intrinsics,
                                        const Pose3& odom_camera,
                                        MotionSource source = MotionSource::kVision,
                                        std::optional<Time> depth_stamp = std::nullopt);
  // Forgets the last keyframe (the next acceptable frame becomes one).
  void Reset();
  size_t num_keyframes() const { return next_id_; }

 private:
  KeyframerOptions options_;
  std::optional<Pose3> last_odom_camera_;
  // The previous offered frame (stamp, T_odom_camera): with the current one, the velocity.
  std::optional<std::pair<Time, Pose3>> previous_frame_;
  int frames_since_keyframe_ = 0;
  size_t next_id_ = 0;
  size_t frame_index_ = 0;
};

}  // namespace icgm
