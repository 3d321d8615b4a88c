#include "core/slam/observation_keyframer.h"

#include <cmath>
#include <limits>

#include "core/common/option_reader.h"
#include "core/registration/depth_points.h"
#include "core/registration/sensor_timing.h"

namespace icgm {

void ReadOptions(const OptionReader& r, KeyframerOptions* o) {
  r.Read("min_translation_m", &o->min_translation_m, 0.0, 100.0);
  r.Read("min_rotation_deg", &o->min_rotation_deg, 0.0, 180.0);
  r.Read("max_interval_frames", &o->max_interval_frames, 1, 100000);
  r.Read("min_robust_points", &o->min_robust_points, 0, 100000);
  r.Read("min_depth_m", &o->depth.min_depth_m, 0.0, 100.0);
  r.Read("max_depth_m", &o->depth.max_depth_m, 0.0, 100.0);
  r.Read("max_depth_jump_ratio", &o->depth.max_depth_jump_ratio, -1.0, 10.0);
  if (o->depth.max_depth_m <= o->depth.min_depth_m) {
    throw LoadError(r.path() + ": max_depth_m must exceed min_depth_m");
  }
  r.Read("compensate_sensor_timing", &o->compensate_sensor_timing);
  r.Read("max_velocity_gap_s", &o->max_velocity_gap_s, 0.0, 10.0);
  r.Read("depth_timing_min_s", &o->depth_timing_min_s, 0.0, 1.0);
}

void ObservationKeyframer::Reset() {
  last_odom_camera_.reset();
  previous_frame_.reset();
  frames_since_keyframe_ = 0;
}

std::optional<FrontendKeyframe> ObservationKeyframer::Offer(const TrackedFrame& frame,
                                                            const cv::Mat& depth_m,
                                                            const CameraIntrinsics& intrinsics,
                                                            const Pose3& odom_camera,
                                                            MotionSource source,
                                                            std::optional<Time> depth_stamp) {
  const size_t frame_index = frame_index_++;
  ++frames_since_keyframe_;
  if (!odom_camera.matrix().allFinite()) return std::nullopt;
  std::optional<Vec6> twist;
  if (previous_frame_ && options_.compensate_sensor_timing) {
    twist = VelocityTwist(previous_frame_->first, previous_frame_->second, frame.stamp,
                          odom_camera, options_.max_velocity_gap_s);
  }
  previous_frame_.emplace(frame.stamp, odom_camera);
  if (last_odom_camera_) {
    const Pose3 motion = Between(*last_odom_camera_, odom_camera);
    const bool moved = TranslationNorm(motion) >= options_.min_translation_m ||
                       RotationAngleRad(motion) * 180.0 / M_PI >= options_.min_rotation_deg ||
                       frames_since_keyframe_ >= options_.max_interval_frames;
    if (!moved) return std::nullopt;
  }
  // The sensor's calibrated depth scale, applied here as the front end applies it; then depth
  // and keypoints at the colour stamp's instant.
  cv::Mat depth = CorrectedDepth(depth_m, intrinsics);
  FeatureSet features = frame.features;
  if (twist && depth.type() == CV_32FC1) {
    const double depth_dt_s = DepthTimeOffsetS(frame.stamp, depth_stamp.value_or(frame.stamp),
                                               intrinsics, options_.depth_timing_min_s);
    depth = DepthAtStamp(depth, intrinsics, depth_dt_s, *twist);
    KeypointsAtStamp(intrinsics, *twist, depth, &features.keypoints);
  }
  std::vector<cv::Point2f> pixels;
  pixels.reserve(features.keypoints.size());
  for (const auto& k : features.keypoints) pixels.push_back(k.pt);
  std::vector<Eigen::Vector3d> points;
  std::vector<uint8_t> valid;
  KeypointsToPoints(pixels, depth, intrinsics, options_.depth, &points, &valid);
  int robust_points = 0;
  for (size_t i = 0; i < points.size(); ++i) {
    const bool robust = i < frame.robust.size() && frame.robust[i];
    if (!valid[i]) points[i].setConstant(std::numeric_limits<double>::quiet_NaN());
    robust_points += robust && valid[i];
  }
  if (robust_points < options_.min_robust_points) return std::nullopt;

  FrontendKeyframe kf;
  kf.id = next_id_++;
  kf.frame_index = frame_index;
  kf.stamp = frame.stamp;
  kf.odom_camera = odom_camera;
  kf.relative_pose = last_odom_camera_ ? Between(*last_odom_camera_, odom_camera) : Pose3::Identity();
  kf.relative_source = last_odom_camera_ ? source : MotionSource::kNone;
  kf.features = std::move(features);
  kf.points_m = std::move(points);
  kf.robust = frame.robust;
  kf.robust.resize(kf.features.keypoints.size(), 0);
  kf.depth_m = depth;
  last_odom_camera_ = odom_camera;
  frames_since_keyframe_ = 0;
  return kf;
}

}  // namespace icgm
