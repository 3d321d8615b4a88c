#include "core/odometry/odometry_fusion.h"

#include <cmath>

#include "core/common/option_reader.h"

namespace icgm {

const char* MotionSourceName(MotionSource source) {
  switch (source) {
    case MotionSource::kVision:
      return "vision";
    case MotionSource::kWheel:
      return "wheel";
    case MotionSource::kConstantVelocity:
      return "constant_velocity";
    case MotionSource::kNone:
      return "none";
  }
  return "unknown";
}

Pose3 CameraMotionFromBase(const Pose3& base_motion, const Pose3& base_to_camera) {
  return base_to_camera.inverse() * base_motion * base_to_camera;
}

void ReadOptions(const OptionReader& reader, FusionOptions* options) {
  reader.Read("constant_velocity_fallback", &options->constant_velocity_fallback);
  reader.Read("max_constant_velocity_s", &options->max_constant_velocity_s, 0.0, 60.0);
  reader.Read("max_vision_wheel_disagreement_m", &options->max_vision_wheel_disagreement_m, 0.0,
              100.0);
  reader.Read("max_vision_wheel_disagreement_deg", &options->max_vision_wheel_disagreement_deg, 0.0,
              180.0);
  Vec3 t = options->base_to_camera.translation();
  reader.Read("base_to_camera_x_m", &t.x(), -100.0, 100.0);
  reader.Read("base_to_camera_y_m", &t.y(), -100.0, 100.0);
  reader.Read("base_to_camera_z_m", &t.z(), -100.0, 100.0);
  const Eigen::Vector3d ypr = options->base_to_camera.linear().eulerAngles(2, 1, 0);
  double roll = ypr[2] * 180.0 / M_PI, pitch = ypr[1] * 180.0 / M_PI, yaw = ypr[0] * 180.0 / M_PI;
  reader.Read("base_to_camera_roll_deg", &roll, -360.0, 360.0);
  reader.Read("base_to_camera_pitch_deg", &pitch, -360.0, 360.0);
  reader.Read("base_to_camera_yaw_deg", &yaw, -360.0, 360.0);
  const double d = M_PI / 180.0;
  const Quat q = Eigen::AngleAxisd(yaw * d, Vec3::UnitZ()) *
                 Eigen::AngleAxisd(pitch * d, Vec3::UnitY()) *
                 Eigen::AngleAxisd(roll * d, Vec3::UnitX());
  options->base_to_camera = MakePose(t, q);
}

size_t FusionStats::total_frames() const {
  size_t n = 0;
  for (size_t f : frames) n += f;
  return n;
}

double FusionStats::total_distance_m() const {
  double d = 0.0;
  for (double x : distance_m) d += x;
  return d;
}

double FusionStats::VisionShareByFrames() const {
  const size_t n = total_frames();
  return n == 0 ? 0.0 : static_cast<double>(frames[0]) / n;
}

double FusionStats::VisionShareByDistance() const {
  const double d = total_distance_m();
  return d <= 0.0 ? 0.0 : distance_m[0] / d;
}

OdometryFusion::OdometryFusion(const FusionOptions& options) : options_(options) {}

void OdometryFusion::Initialize(Time stamp, const WheelOdometryBuffer* wheel) {
  Pose3 odom_base = Pose3::Identity();
  if (wheel) {
    Pose3 p;
    if (wheel->PoseAt(stamp, &p).ok()) odom_base = p;
  }
  odom_camera_ = odom_base * options_.base_to_camera;
  stamp_ = stamp;
  initialized_ = true;
  has_velocity_ = false;
  extrapolated_s_ = 0.0;
}

Status OdometryFusion::WheelStep(Time stamp, const WheelOdometryBuffer* wheel,
                                 Pose3* camera_prev_cur) const {
  if (!wheel) return Status::Error("no wheel odometry source");
  Pose3 base_rel;
  const Status s = wheel->RelativeMotion(stamp_, stamp, &base_rel);
  if (s.ok()) {
    *camera_prev_cur = CameraMotionFromBase(base_rel, options_.base_to_camera);
  }
  return s;
}

bool OdometryFusion::ConstantVelocityStep(Time stamp, Pose3* camera_prev_cur) const {
  const double dt = DurationSeconds(stamp, stamp_);
  if (!options_.constant_velocity_fallback || !has_velocity_ || dt <= 0.0 ||
      extrapolated_s_ + dt > options_.max_constant_velocity_s) {
    return false;
  }
  *camera_prev_cur = ExpSE3(velocity_ * dt);
  return true;
}

MotionSource OdometryFusion::Predict(Time stamp, const WheelOdometryBuffer* wheel,
                                     Pose3* camera_prev_cur) const {
  if (!initialized_) return MotionSource::kNone;
  if (WheelStep(stamp, wheel, camera_prev_cur).ok()) return MotionSource::kWheel;
  if (ConstantVelocityStep(stamp, camera_prev_cur)) return MotionSource::kConstantVelocity;
  return MotionSource::kNone;
}

FusionStep OdometryFusion::Update(Time stamp, const Pose3* vision_prev_cur,
                                  const WheelOdometryBuffer* wheel) {
  FusionStep step;
  if (!initialized_) {
    Initialize(stamp, wheel);
    return step;  // kNone, identity: the first frame defines the origin
  }
  const double dt = DurationSeconds(stamp, stamp_);
  if (vision_prev_cur && options_.max_vision_wheel_disagreement_m > 0.0) {
    Pose3 wheel_step;
    if (WheelStep(stamp, wheel, &wheel_step).ok()) {
      const Pose3 diff = Between(wheel_step, *vision_prev_cur);
      const double dt_m = TranslationNorm(diff);
      const double dr_deg = RotationAngleRad(diff) * 180.0 / M_PI;
      const double max_deg = options_.max_vision_wheel_disagreement_deg > 0.0
                                 ? options_.max_vision_wheel_disagreement_deg
                                 : 180.0;
      if (dt_m > options_.max_vision_wheel_disagreement_m || dr_deg > max_deg) {
        step.vision_rejected =
            Status::Error("visual step disagrees with wheel odometry by " + std::to_string(dt_m) +
                          " m, " + std::to_string(dr_deg) + " deg");
        vision_prev_cur = nullptr;
      }
    }
  }
  if (vision_prev_cur) {
    step.source = MotionSource::kVision;
    step.camera_prev_cur = *vision_prev_cur;
  } else {
    step.wheel_status = WheelStep(stamp, wheel, &step.camera_prev_cur);
    if (step.wheel_status.ok()) {
      step.source = MotionSource::kWheel;
    } else if (ConstantVelocityStep(stamp, &step.camera_prev_cur)) {
      step.source = MotionSource::kConstantVelocity;
    }
  }

  if (step.source == MotionSource::kVision || step.source == MotionSource::kWheel) {
    if (dt > 0.0) {
      velocity_ = LogSE3(step.camera_prev_cur) / dt;
      has_velocity_ = true;
    }
    extrapolated_s_ = 0.0;
  } else {
    extrapolated_s_ += std::max(0.0, dt);
  }
  const size_t k = static_cast<size_t>(step.source);
  ++stats_.frames[k];
  stats_.distance_m[k] += TranslationNorm(step.camera_prev_cur);

  // Re-orthonormalized every step: rounding in the composed rotation would otherwise grow
  // (Isometry inverses use the transpose, which feeds any drift back).
  odom_camera_ = Orthonormalized(odom_camera_ * step.camera_prev_cur);
  stamp_ = stamp;
  return step;
}

}  // namespace icgm
