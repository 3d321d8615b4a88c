#include "core/sim/simulator.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "core/common/status.h"
#include "core/sim/frame_render.h"
#include "core/sim/random_streams.h"

namespace icgm::sim {
Pose3 CameraMountPose(const CameraMountOptions& m) {
  Eigen::Matrix3d base_from_optical;
  base_from_optical.col(0) = Eigen::Vector3d(0, -1, 0);  // optical x = right = -y_base
  base_from_optical.col(1) = Eigen::Vector3d(0, 0, -1);  // optical y = down = -z_base
  base_from_optical.col(2) = Eigen::Vector3d(1, 0, 0);   // optical z = forward = x_base
  const double deg = M_PI / 180.0;
  Pose3 T = Pose3::Identity();
  T.linear() = (Eigen::AngleAxisd(m.yaw_left_deg * deg, Eigen::Vector3d::UnitZ()) *
                Eigen::AngleAxisd(m.pitch_down_deg * deg, Eigen::Vector3d::UnitY()))
                   .toRotationMatrix() *
               base_from_optical;
  T.translation() = Eigen::Vector3d(m.forward_m, 0.0, m.height_m);
  return T;
}

size_t Simulator::NumFrames(const SimOptions& o, const LoopRoute& route) {
  if (o.route.laps > 0.0 && !o.handheld_camera()) {
    return static_cast<size_t>(std::ceil(route.DurationForLaps(o.route.laps) * o.frame_rate_hz)) +
           1;
  }
  return static_cast<size_t>(o.num_frames);
}

void Simulator::BuildWheeledPath(size_t n, double dt) {
  const double duration =
      options_.route.laps > 0.0 ? route_.DurationForLaps(options_.route.laps) : (n - 1) * dt;
  for (size_t i = 0; i < n; ++i) {
    planar_.push_back(route_.PoseAt(route_.ArcLengthAt(i * dt, duration)));
    T_world_base_.push_back(ToPose3(planar_.back()));
    T_world_camera_.push_back(T_world_base_.back() * T_base_camera_);
  }
  Rng odometry_rng(StreamSeed(options_.seed, Stream::kOdometry));
  odometry_ = SimulateWheelOdometry(planar_, dt, options_.odometry, odometry_rng);
}

void Simulator::BuildHandheldPath(size_t n, double dt) {
  Rng rng(StreamSeed(options_.seed, Stream::kHandheld));
  handheld_ = HandheldMotion(options_.handheld, (n - 1) * dt, rng);
  for (size_t i = 0; i < n; ++i) {
    T_world_camera_.push_back(handheld_.T_world_camera(i * dt));
    planar_.push_back(handheld_.ViewOnFloor(i * dt));
  }
}

Pose3 Simulator::CameraPoseAt(double t_s) const {
  if (options_.handheld_camera()) return handheld_.T_world_camera(t_s);
  const double f = std::clamp(t_s * options_.frame_rate_hz, 0.0, double(size() - 1));
  const size_t i = std::min(static_cast<size_t>(f), size() - 1);
  const size_t j = std::min(i + 1, size() - 1);
  const double a = f - i;
  const Pose3& A = T_world_camera_[i];
  const Pose3& B = T_world_camera_[j];
  Pose3 T = Pose3::Identity();
  T.linear() = Eigen::Quaterniond(A.linear())
                   .slerp(a, Eigen::Quaterniond(B.linear()))
                   .toRotationMatrix();
  T.translation() = (1.0 - a) * A.translation() + a * B.translation();
  return T;
}

Simulator::Simulator(const SimOptions& options)
    : options_(options),
      route_(options.room, options.route),
      T_base_camera_(options.handheld_camera() ? Pose3::Identity()
                                               : CameraMountPose(options.camera_mount)),
      caster_(options.intrinsics) {
  if (!options_.intrinsics.Valid()) throw LoadError("simulator: invalid camera intrinsics");
  const size_t n = NumFrames(options_, route_);
  if (n == 0) throw LoadError("simulator: no frames to render");
  const double dt = 1.0 / options_.frame_rate_hz;
  const int64_t start_ns = static_cast<int64_t>(std::llround(options_.start_time_s * 1e9));
  for (size_t i = 0; i < n; ++i) {
    const int64_t offset_ns = static_cast<int64_t>(std::llround(i * dt * 1e9));
    stamps_.push_back(Time::FromNanoseconds(start_ns + offset_ns));
  }
  Rng world_rng(StreamSeed(options_.seed, Stream::kWorld));
  if (options_.handheld_camera()) {
    BuildHandheldPath(n, dt);
    // Furniture keeps clear of the camera's positions (sampled every 0.5 s).
    std::vector<Eigen::Vector2d> path;
    const size_t every = std::max<size_t>(1, static_cast<size_t>(0.5 / dt));
    for (size_t i = 0; i < n; i += every) path.emplace_back(planar_[i].x_m, planar_[i].y_m);
    scene_ = BuildCafeteria(
        options_.room,
        [&path](double x, double y) {
          double d = std::numeric_limits<double>::infinity();
          for (const auto& p : path) d = std::min(d, std::hypot(x - p.x(), y - p.y()));
          return d;
        },
        world_rng);
  } else {
    BuildWheeledPath(n, dt);
    scene_ = BuildCafeteria(options_.room, route_, world_rng);
  }
  Rng crowd_rng(StreamSeed(options_.effective_crowd_seed(), Stream::kCrowd));
  // Crossing walkers aim across the camera's view: the handheld camera's planar pose already
  // looks along it; the robot's camera looks yaw_left_deg off its heading.
  const double view_yaw_rad =
      options_.handheld_camera() ? 0.0 : options_.camera_mount.yaw_left_deg * M_PI / 180.0;
  crowd_ = Crowd(options_.crowd, scene_, planar_, view_yaw_rad, dt, options_.room.texel_size_m,
                 crowd_rng);
}

SimFrame Simulator::Render(size_t i, const RenderFlags& flags) const {
  SimFrame f;
  f.index = i;
  f.stamp = stamps_[i];
  f.T_world_camera = T_world_camera_[i];
  if (has_wheel_odometry()) {
    f.T_world_base = T_world_base_[i];
    f.odometry = odometry_[i];
  }
  std::vector<CylinderPrimitive> dynamic;
  if (flags.pedestrians) crowd_.AppendBodyParts(i, &dynamic);
  const double t = i / options_.frame_rate_hz;
  const Pose3 T_camera_world = f.T_world_camera.inverse();
  RenderSensorFrame(
      options_, caster_, scene_, dynamic, i, flags,
      [&](double offset_s) { return T_camera_world * CameraPoseAt(t + offset_s); }, &f);
  return f;
}

}  // namespace icgm::sim
