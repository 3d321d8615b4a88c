#include "core/sim/closed_loop_simulator.h"

#include <algorithm>
#include <cmath>

#include "core/common/status.h"
#include "core/sim/frame_render.h"
#include "core/sim/random_streams.h"
#include "core/sim/scan_render.h"

namespace icgm::sim {
namespace {

// Pose after moving with constant forward speed v and turn rate w for t seconds (exact arc).
PlanarPose Advance(const PlanarPose& p, double v, double w, double t) {
  PlanarPose q = p;
  const double dyaw = w * t;
  if (std::abs(dyaw) < 1e-9) {
    q.x_m += v * t * std::cos(p.yaw_rad + 0.5 * dyaw);
    q.y_m += v * t * std::sin(p.yaw_rad + 0.5 * dyaw);
  } else {
    const double r = v / w;
    q.x_m += r * (std::sin(p.yaw_rad + dyaw) - std::sin(p.yaw_rad));
    q.y_m -= r * (std::cos(p.yaw_rad + dyaw) - std::cos(p.yaw_rad));
  }
  q.yaw_rad = std::remainder(p.yaw_rad + dyaw, 2.0 * M_PI);
  return q;
}

// Moves `current` towards `target` by at most max_change.
double Ramp(double current, double target, double max_change) {
  return current + std::clamp(target - current, -max_change, max_change);
}

// Distance from (x, y) to a box's footprint (0 inside).
double DistanceToFootprint(const BoxPrimitive& b, double x, double y) {
  const double dx = std::max({double(b.min_m.x()) - x, 0.0, x - double(b.max_m.x())});
  const double dy = std::max({double(b.min_m.y()) - y, 0.0, y - double(b.max_m.y())});
  return std::hypot(dx, dy);
}

void Record(double clearance_m, bool* in_contact, CollisionStats* stats) {
  stats->min_clearance_m = std::min(stats->min_clearance_m, clearance_m);
  const bool contact = clearance_m < 0.0;
  if (contact && !*in_contact) ++stats->collisions;
  *in_contact = contact;
}

}  // namespace

ClosedLoopSimulator::ClosedLoopSimulator(const SimOptions& options,
                                         const std::optional<PlanarPose>& start)
    : options_(options),
      route_(options.room, options.route),
      T_base_camera_(CameraMountPose(options.camera_mount)),
      caster_(options.intrinsics),
      drive_rng_(StreamSeed(options.seed, Stream::kDrive)),
      odometry_rng_(StreamSeed(options.seed, Stream::kOdometry)),
      odometry_(options.odometry) {
  if (options_.handheld_camera()) {
    throw LoadError("closed-loop simulator: needs a wheeled robot (camera_motion: wheeled)");
  }
  if (!options_.intrinsics.Valid()) throw LoadError("simulator: invalid camera intrinsics");
  stamp_ = Time::FromNanoseconds(static_cast<int64_t>(std::llround(options_.start_time_s * 1e9)));
  pose_ = start ? *start : route_.PoseAt(0.0);
  // The same world as Simulator builds for these options.
  Rng world_rng(StreamSeed(options_.seed, Stream::kWorld));
  scene_ = BuildCafeteria(options_.room, route_, world_rng);
  crowd_ = CrowdStepper(
      options_.crowd, scene_, CrowdView(), options_.camera_mount.yaw_left_deg * M_PI / 180.0,
      options_.room.texel_size_m, Rng(StreamSeed(options_.effective_crowd_seed(), Stream::kCrowd)));
  person_contact_.assign(crowd_.num_pedestrians(), false);
  UpdateCollisions();
}

Pose3 ClosedLoopSimulator::T_world_base() const { return ToPose3(pose_); }

CrowdRobot ClosedLoopSimulator::CrowdView() const {
  CrowdRobot r;
  r.base = pose_;
  // Crossing walkers anticipate the robot keeping its current velocity.
  r.base_ahead = Advance(pose_, velocity_.linear_mps, velocity_.angular_radps, kCrowdLookaheadS);
  r.camera_xy = T_world_camera().translation().head<2>();
  // People see the whole robot, not only its camera: non-yielding walkers do not step into it.
  r.footprint_radius_m = options_.drive.robot_radius_m;
  return r;
}

void ClosedLoopSimulator::StepRobot(const VelocityCommand& cmd, double dt_s) {
  const DriveOptions& d = options_.drive;
  const double v_cmd = std::clamp(cmd.linear_mps, -d.max_linear_mps, d.max_linear_mps);
  const double w_cmd = std::clamp(cmd.angular_radps, -d.max_angular_radps, d.max_angular_radps);
  ramped_.linear_mps = Ramp(ramped_.linear_mps, v_cmd, d.max_linear_accel_mps2 * dt_s);
  ramped_.angular_radps = Ramp(ramped_.angular_radps, w_cmd, d.max_angular_accel_radps2 * dt_s);
  std::normal_distribution<double> normal(0.0, 1.0);
  const double nv = normal(drive_rng_), nw = normal(drive_rng_);
  velocity_.linear_mps = std::clamp(ramped_.linear_mps * (1.0 + d.linear_noise_fraction * nv),
                                    -d.max_linear_mps, d.max_linear_mps);
  velocity_.angular_radps =
      std::clamp(ramped_.angular_radps * (1.0 + d.angular_noise_fraction * nw),
                 -d.max_angular_radps, d.max_angular_radps);
  pose_ = Advance(pose_, velocity_.linear_mps, velocity_.angular_radps, dt_s);
  distance_m_ += std::abs(velocity_.linear_mps) * dt_s;
}

void ClosedLoopSimulator::Step(const VelocityCommand& cmd, double dt_s) {
  if (!(dt_s > 0.0)) return;
  const PlanarPose before = pose_;
  StepRobot(cmd, dt_s);
  odometry_.Step(before, pose_, dt_s, odometry_rng_);
  crowd_.Step(CrowdView(), dt_s);
  elapsed_s_ += dt_s;
  ++num_steps_;
  stamp_ = Time::FromNanoseconds(static_cast<int64_t>(std::llround(options_.start_time_s * 1e9)) +
                                 static_cast<int64_t>(std::llround(elapsed_s_ * 1e9)));
  UpdateCollisions();
}

double ClosedLoopSimulator::StaticClearanceM() const {
  const double x = pose_.x_m, y = pose_.y_m;
  double d = std::min({x, y, double(scene_.room.width_m) - x, double(scene_.room.length_m) - y});
  for (const BoxPrimitive& b : scene_.boxes) d = std::min(d, DistanceToFootprint(b, x, y));
  return d - options_.drive.robot_radius_m;
}

double ClosedLoopSimulator::PedestrianClearanceM() const {
  double d = std::numeric_limits<double>::infinity();
  const std::vector<PedestrianState> people = crowd_.States();
  for (size_t i = 0; i < people.size(); ++i) {
    d = std::min(
        d, std::hypot(people[i].x_m - pose_.x_m, people[i].y_m - pose_.y_m) - crowd_.radius_m(i));
  }
  return d - options_.drive.robot_radius_m;
}

double ClosedLoopSimulator::min_clearance_m() const {
  return std::min(static_stats_.min_clearance_m, people_stats_.min_clearance_m);
}

void ClosedLoopSimulator::UpdateCollisions() {
  Record(StaticClearanceM(), &static_contact_, &static_stats_);
  const std::vector<PedestrianState> people = crowd_.States();
  for (size_t i = 0; i < people.size(); ++i) {
    const double clearance = std::hypot(people[i].x_m - pose_.x_m, people[i].y_m - pose_.y_m) -
                             crowd_.radius_m(i) - options_.drive.robot_radius_m;
    bool contact = person_contact_[i];
    Record(clearance, &contact, &people_stats_);
    person_contact_[i] = contact;
  }
}

SimFrame ClosedLoopSimulator::Render(const RenderFlags& flags) const {
  SimFrame f;
  f.index = num_steps_;
  f.stamp = stamp_;
  f.T_world_base = T_world_base();
  f.T_world_camera = T_world_camera();
  f.odometry = odometry_.sample();
  std::vector<CylinderPrimitive> dynamic;
  if (flags.pedestrians) crowd_.AppendBodyParts(&dynamic);
  // The camera keeps its current velocity during the exposure.
  const double v = velocity_.linear_mps, w = velocity_.angular_radps;
  const Pose3 T_camera_world = f.T_world_camera.inverse();
  RenderSensorFrame(options_, caster_, scene_, dynamic, num_steps_, flags,
                    [&](double offset_s) {
                      return T_camera_world * ToPose3(Advance(pose_, v, w, offset_s)) *
                             T_base_camera_;
                    },
                    &f);
  return f;
}

PlanarScan ClosedLoopSimulator::RenderScan() const {
  std::vector<CylinderPrimitive> dynamic;
  crowd_.AppendBodyParts(&dynamic);
  Rng rng(StreamSeed(options_.seed, Stream::kScan, num_steps_));
  return RenderPlanarScan(options_.scanner, scene_, dynamic, pose_, stamp_, rng);
}

Pose3 ClosedLoopSimulator::T_base_scanner() const { return ScannerMountPose(options_.scanner); }

}  // namespace icgm::sim
