// Per-frame choice of the motion source and accumulation of the global pose (thesis ch. 6.1.1.1,
// eq. 6.1: L_n = L_(n-1) (+) R_n). R_n is the visual 6-D rigid transformation when registration
// succeeded; otherwise the wheel odometry motion over the same time span, moved into the camera
// frame with the static extrinsic T_base_camera,
//     R_cam = T_base_camera^-1 * R_base * T_base_camera;
// when neither is available, the last velocity is held for up to max_constant_velocity_s
// (flagged kConstantVelocity), after which the pose stays put (kNone).
//
// The shares of frames and of travelled distance that came from vision are counted; the thesis
// reports 97.6% of the relative poses from RGB-D registration.
#pragma once

#include <array>
#include <cstddef>
#include <string>

#include "core/common/pose.h"
#include "core/common/status.h"
#include "core/common/time.h"
#include "core/odometry/wheel_odometry_buffer.h"

namespace icgm {

class OptionReader;

enum class MotionSource { kVision = 0, kWheel = 1, kConstantVelocity = 2, kNone = 3 };
constexpr size_t kNumMotionSources = 4;
const char* MotionSourceName(MotionSource source);

struct FusionOptions {
  // Static extrinsic: p_base = base_to_camera * p_camera (base_link -> camera optical frame).
  Pose3 base_to_camera = Pose3::Identity();
  bool constant_velocity_fallback = true;
  double max_constant_velocity_s = 0.5;
  // Vision/wheel consistency gate: when wheel odometry covers the span and the visual step
  // differs from it by more than this (translation, rotation), the visual step is taken to have
  // locked onto something moving (a walker filling the view) and the wheel step is used.
  // <= 0 disables. The thesis trusts vision whenever registration succeeds.
  double max_vision_wheel_disagreement_m = 0.03;
  double max_vision_wheel_disagreement_deg = 1.5;
};

// Reads a `fusion:` section: constant_velocity_fallback, max_constant_velocity_s and the
// extrinsic as base_to_camera_{x,y,z}_m and base_to_camera_{roll,pitch,yaw}_deg (fixed-axis
// roll-pitch-yaw, R = Rz(yaw) Ry(pitch) Rx(roll), as in URDF/tf). Throws LoadError.
void ReadOptions(const OptionReader& reader, FusionOptions* options);

// The base's motion T_base(a)_base(b) as the camera mounted at `base_to_camera` moves:
// base_to_camera^-1 * base_motion * base_to_camera.
Pose3 CameraMotionFromBase(const Pose3& base_motion, const Pose3& base_to_camera);

struct FusionStats {
  std::array<size_t, kNumMotionSources> frames{};
  std::array<double, kNumMotionSources> distance_m{};
  size_t total_frames() const;
  double total_distance_m() const;
  // Share of updates (by count / by camera translation) whose motion came from vision, in [0, 1].
  double VisionShareByFrames() const;
  double VisionShareByDistance() const;
};

struct FusionStep {
  MotionSource source = MotionSource::kNone;
  // Camera motion from the previous frame: p_prev = camera_prev_cur * p_cur.
  Pose3 camera_prev_cur = Pose3::Identity();
  // Why the wheel odometry was not used (ok when used or not needed).
  Status wheel_status = Status::Ok();
  // Why a successful visual step was overruled by the consistency gate (ok otherwise).
  Status vision_rejected = Status::Ok();
};

class OdometryFusion {
 public:
  explicit OdometryFusion(const FusionOptions& options = FusionOptions());

  // First frame: starts the odometry frame at the wheel odometry pose when available at `stamp`
  // (so T_odom_base equals the wheel pose), else with the base at the origin.
  void Initialize(Time stamp, const WheelOdometryBuffer* wheel);
  bool initialized() const { return initialized_; }

  // Advances to `stamp`. `vision_prev_cur` is the visual camera motion since the previous frame
  // (nullptr when registration failed); `wheel` may be nullptr.
  FusionStep Update(Time stamp, const Pose3* vision_prev_cur, const WheelOdometryBuffer* wheel);

  // Predicted camera motion from the last update to `stamp` (p_prev = *camera_prev_cur * p_cur),
  // before any visual measurement: the wheel odometry over the span through the extrinsic, else
  // the last velocity (within max_constant_velocity_s when constant_velocity_fallback is on).
  // Returns the source used; kNone (nothing written) when neither is available or before the
  // first update.
  MotionSource Predict(Time stamp, const WheelOdometryBuffer* wheel, Pose3* camera_prev_cur) const;

  const Pose3& odom_camera() const { return odom_camera_; }
  Pose3 odom_base() const { return odom_camera_ * options_.base_to_camera.inverse(); }
  Time stamp() const { return stamp_; }
  const FusionStats& stats() const { return stats_; }
  const FusionOptions& options() const { return options_; }

 private:
  // Wheel motion from the last update to `stamp` in the camera frame (through the extrinsic);
  // writes *camera_prev_cur only on success.
  Status WheelStep(Time stamp, const WheelOdometryBuffer* wheel, Pose3* camera_prev_cur) const;
  // The last velocity held to `stamp`, when the fallback is on and still within
  // max_constant_velocity_s; writes *camera_prev_cur only then.
  bool ConstantVelocityStep(Time stamp, Pose3* camera_prev_cur) const;

  FusionOptions options_;
  bool initialized_ = false;
  Time stamp_;
  Pose3 odom_camera_ = Pose3::Identity();
  // Last measured camera velocity as a twist per second, and time spent extrapolating it.
  Eigen::Matrix<double, 6, 1> velocity_ = Eigen::Matrix<double, 6, 1>::Zero();
  bool has_velocity_ = false;
  double extrapolated_s_ = 0.0;
  FusionStats stats_;
};

}  // namespace icgm
