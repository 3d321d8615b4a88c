#include "core/sim/simulator.h"

#include <cmath>

#include "core/common/status.h"
#include "core/sim/depth_noise.h"

namespace icgm::sim {
namespace {

// Independent random streams per purpose (and per frame), so that e.g. adding pedestrians does
// not change the furniture and frame i looks the same whatever order frames are rendered in.
enum class Stream : uint64_t { kWorld = 1, kCrowd = 2, kOdometry = 3, kFrame = 4 };

uint64_t StreamSeed(int seed, Stream stream, uint64_t index = 0) {
  // SplitMix64 finalizer over the combined key.
  uint64_t z = static_cast<uint64_t>(seed) * 0x9E3779B97F4A7C15ull +
               static_cast<uint64_t>(stream) * 0xBF58476D1CE4E5B9ull +
               index * 0x94D049BB133111EBull;
  z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
  z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
  return z ^ (z >> 31);
}

}  // namespace

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
  if (o.route.laps > 0.0) {
    return static_cast<size_t>(std::ceil(route.DurationForLaps(o.route.laps) * o.frame_rate_hz)) +
           1;
  }
  return static_cast<size_t>(o.num_frames);
}

Simulator::Simulator(const SimOptions& options)
    : options_(options),
      route_(options.room, options.route),
      T_base_camera_(CameraMountPose(options.camera_mount)),
      caster_(options.intrinsics) {
  if (!options_.intrinsics.Valid()) throw LoadError("simulator: invalid camera intrinsics");
  const size_t n = NumFrames(options_, route_);
  if (n == 0) throw LoadError("simulator: no frames to render");
  const double dt = 1.0 / options_.frame_rate_hz;
  const double duration =
      options_.route.laps > 0.0 ? route_.DurationForLaps(options_.route.laps) : (n - 1) * dt;
  const int64_t start_ns = static_cast<int64_t>(std::llround(options_.start_time_s * 1e9));
  for (size_t i = 0; i < n; ++i) {
    const int64_t offset_ns = static_cast<int64_t>(std::llround(i * dt * 1e9));
    stamps_.push_back(Time::FromNanoseconds(start_ns + offset_ns));
    planar_.push_back(route_.PoseAt(route_.ArcLengthAt(i * dt, duration)));
    T_world_base_.push_back(ToPose3(planar_.back()));
  }
  Rng odometry_rng(StreamSeed(options_.seed, Stream::kOdometry));
  odometry_ = SimulateWheelOdometry(planar_, dt, options_.odometry, odometry_rng);
  Rng world_rng(StreamSeed(options_.seed, Stream::kWorld));
  scene_ = BuildCafeteria(options_.room, route_, world_rng);
  Rng crowd_rng(StreamSeed(options_.seed, Stream::kCrowd));
  crowd_ = Crowd(options_.crowd, scene_, planar_, options_.camera_mount.yaw_left_deg * M_PI / 180.0,
                 dt, options_.room.texel_size_m, crowd_rng);
}

SimFrame Simulator::Render(size_t i, const RenderFlags& flags) const {
  SimFrame f;
  f.index = i;
  f.stamp = stamps_[i];
  f.T_world_base = T_world_base_[i];
  f.T_world_camera = T_world_camera(i);
  f.odometry = odometry_[i];
  std::vector<CylinderPrimitive> dynamic;
  if (flags.pedestrians) crowd_.AppendBodyParts(i, &dynamic);
  IdealImage ideal;
  caster_.Render(scene_, dynamic, f.T_world_camera, &ideal);
  f.bgr = ideal.bgr;
  f.dynamic_mask = ideal.mask;
  if (!flags.sensor_effects) {
    f.depth_m = ideal.depth_m;
    return f;
  }
  Rng frame_rng(StreamSeed(options_.seed, Stream::kFrame, i));
  ApplyDepthNoise(options_.depth_noise, ideal.depth_m, frame_rng, &f.depth_m);
  AddNoise(frame_rng, options_.image_noise_sigma, false, &f.bgr);
  return f;
}

}  // namespace icgm::sim
