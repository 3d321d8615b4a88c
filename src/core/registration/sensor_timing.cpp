#include "core/registration/sensor_timing.h"

#include <cmath>

#include "core/registration/depth_warp.h"

namespace icgm {

std::optional<Vec6> VelocityTwist(Time t0, const Pose3& odom_camera_t0, Time t1,
                                  const Pose3& odom_camera_t1, double max_gap_s) {
  const double gap_s = DurationSeconds(t1, t0);
  if (!(gap_s > 0.0) || gap_s > max_gap_s) return std::nullopt;
  // Constant body velocity over [t0, t1]: T(t + dt) = T(t) * Exp(dt * twist).
  const Vec6 twist = LogSE3(Between(odom_camera_t0, odom_camera_t1)) / gap_s;
  if (!twist.allFinite()) return std::nullopt;
  return twist;
}

double DepthTimeOffsetS(Time colour_stamp, Time depth_stamp, const CameraIntrinsics& intrinsics,
                        double min_s) {
  const double dt_s =
      DurationSeconds(depth_stamp, colour_stamp) + intrinsics.depth_time_offset_s;
  return std::abs(dt_s) < min_s ? 0.0 : dt_s;
}

bool HasRollingShutter(const CameraIntrinsics& intrinsics) {
  return intrinsics.readout_s > 0.0 || intrinsics.first_row_offset_s != 0.0;
}

RowTiming ColourRowTiming(const CameraIntrinsics& intrinsics) {
  RowTiming timing;
  timing.first_row_s = intrinsics.first_row_offset_s;
  timing.line_s =
      intrinsics.height_px > 1 ? intrinsics.readout_s / (intrinsics.height_px - 1) : 0.0;
  return timing;
}

cv::Mat DepthAtStamp(const cv::Mat& depth_m, const CameraIntrinsics& intrinsics,
                     double depth_dt_s, const Vec6& twist) {
  if (!HasRollingShutter(intrinsics)) {
    if (depth_dt_s == 0.0) return depth_m;
    return WarpDepthImage(depth_m, intrinsics, ExpSE3(depth_dt_s * twist));
  }
  RowTiming timing = ColourRowTiming(intrinsics);
  timing.first_row_s += depth_dt_s;
  return WarpDepthImageByRow(depth_m, intrinsics, StampFromRowPoses(depth_m.rows, timing, twist));
}

void KeypointsAtStamp(const CameraIntrinsics& intrinsics, const Vec6& twist,
                      const cv::Mat& depth_at_stamp_m, std::vector<cv::KeyPoint>* keypoints) {
  if (!HasRollingShutter(intrinsics)) return;
  DeskewKeypoints(StampFromRowPoses(intrinsics.height_px, ColourRowTiming(intrinsics), twist),
                  depth_at_stamp_m, intrinsics, keypoints);
}

}  // namespace icgm
