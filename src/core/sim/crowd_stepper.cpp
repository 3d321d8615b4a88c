#include "core/sim/crowd_stepper.h"

#include <algorithm>
#include <cmath>

namespace icgm::sim {
namespace {

using Vec2f = Eigen::Vector2f;

constexpr float kStrideCycleM = 1.3f;    // distance walked per gait cycle (two steps)
constexpr float kMaxTurnRadPerS = 3.0f;  // how fast a walker can change direction
constexpr float kWallMarginM = 0.3f;

float UniformF(Rng& rng, float lo, float hi) {
  return std::uniform_real_distribution<float>(lo, hi)(rng);
}

// Distance from p to a box's footprint, and the unit direction pointing from the box to p.
float DistanceToFootprint(const BoxPrimitive& b, const Vec2f& p, Vec2f* away) {
  const Vec2f q(std::clamp(p.x(), b.min_m.x(), b.max_m.x()),
                std::clamp(p.y(), b.min_m.y(), b.max_m.y()));
  const Vec2f diff = p - q;
  const float d = diff.norm();
  *away = d > 1e-6f ? Vec2f(diff / d) : Vec2f(1.0f, 0.0f);
  return d;
}

bool FreeSpot(const StaticScene& scene, const Vec2f& p, float radius) {
  const float m = radius + kWallMarginM;
  if (p.x() < m || p.y() < m || p.x() > scene.room.width_m - m || p.y() > scene.room.length_m - m) {
    return false;
  }
  Vec2f away;
  for (const BoxPrimitive& b : scene.boxes) {
    if (DistanceToFootprint(b, p, &away) < radius + 0.05f) return false;
  }
  return true;
}

Vec2f RandomFreeSpot(const StaticScene& scene, float radius, Rng& rng) {
  for (int i = 0; i < 200; ++i) {
    const Vec2f p(UniformF(rng, 0.0f, scene.room.width_m),
                  UniformF(rng, 0.0f, scene.room.length_m));
    if (FreeSpot(scene, p, radius)) return p;
  }
  return Vec2f(0.5f * scene.room.width_m, 0.5f * scene.room.length_m);
}

// A free spot crossing_{min,max}_ahead_m ahead along `view` (the robot's position, looking along
// the camera's horizontal direction), crossing_{min,max}_side_m to its side; `side` = +1 left,
// -1 right.
bool SpotAheadOfRobot(const CrowdOptions& o, const StaticScene& scene, const PlanarPose& view,
                      float side, float radius, Rng& rng, Vec2f* out) {
  const Vec2f r(view.x_m, view.y_m);
  const Vec2f fwd(std::cos(view.yaw_rad), std::sin(view.yaw_rad));
  const Vec2f left(-fwd.y(), fwd.x());
  for (int i = 0; i < 20; ++i) {
    const Vec2f p = r +
                    fwd * UniformF(rng, static_cast<float>(o.crossing_min_ahead_m),
                                   static_cast<float>(o.crossing_max_ahead_m)) +
                    left * side *
                        UniformF(rng, static_cast<float>(o.crossing_min_side_m),
                                 static_cast<float>(o.crossing_max_side_m));
    if (FreeSpot(scene, p, radius)) {
      *out = p;
      return true;
    }
  }
  return false;
}

PlanarPose View(PlanarPose robot, float view_yaw_rad) {
  robot.yaw_rad += view_yaw_rad;
  return robot;
}

// Hard constraint: pedestrians yield to the robot (which may also drive towards a standing one);
// those that do not yield still never walk into the camera.
bool SeesTheRobotsBody(const CrowdRobot& robot, bool yields) {
  return !yields && robot.footprint_radius_m > 0.0;
}

// How close to base_link a non-yielding walker of `radius` comes when it sees the robot's body.
float BodyKeepOut(const CrowdOptions& o, const CrowdRobot& robot, float radius) {
  return static_cast<float>(robot.footprint_radius_m + o.personal_space_m) + radius;
}

void KeepClearOfRobot(const CrowdOptions& o, const CrowdRobot& robot, bool yields, float radius,
                      Vec2f* position) {
  const Vec2f r = yields || SeesTheRobotsBody(robot, yields)
                      ? Vec2f(robot.base.x_m, robot.base.y_m)
                      : robot.camera_xy.cast<float>();
  const float keep_out = SeesTheRobotsBody(robot, yields)
                             ? BodyKeepOut(o, robot, radius)
                             : static_cast<float>(yields ? o.robot_clearance_m : o.personal_space_m) +
                                   radius;
  const Vec2f diff = *position - r;
  if (diff.norm() < keep_out) {
    *position = r + (diff.norm() > 1e-4f ? Vec2f(diff.normalized()) : Vec2f(1.0f, 0.0f)) * keep_out;
  }
}

// A non-yielding walker that sees the robot's body steps from `from` towards `*next` without
// entering its personal space around the body; when the robot came closer than that by itself
// (the walker is not pushed), the walker's step only loses its component towards the robot.
void StepAroundRobotBody(const CrowdOptions& o, const CrowdRobot& robot, float radius,
                         const Vec2f& from, Vec2f* next) {
  const Vec2f r(robot.base.x_m, robot.base.y_m);
  const float keep_out = BodyKeepOut(o, robot, radius);
  if ((*next - r).norm() >= keep_out) return;
  const float from_dist = (from - r).norm();
  if (from_dist >= keep_out) {
    const Vec2f diff = *next - r;
    *next = r + (diff.norm() > 1e-4f ? Vec2f(diff.normalized()) : Vec2f(1.0f, 0.0f)) * keep_out;
    return;
  }
  const Vec2f away = from_dist > 1e-4f ? Vec2f((from - r) / from_dist) : Vec2f(1.0f, 0.0f);
  Vec2f step = *next - from;
  step -= std::min(0.0f, step.dot(away)) * away;
  *next = from + step;
}

}  // namespace

CrowdStepper::CrowdStepper(const CrowdOptions& o, const StaticScene& scene,
                           const std::optional<CrowdRobot>& robot, double view_yaw_rad,
                           double texel_size_m, Rng rng)
    : options_(o), scene_(scene), view_yaw_rad_(static_cast<float>(view_yaw_rad)), rng_(rng) {
  walkers_.resize(o.num_pedestrians);
  looks_.reserve(walkers_.size());
  for (size_t i = 0; i < walkers_.size(); ++i) {
    Walker& w = walkers_[i];
    looks_.push_back(MakePedestrianLook(rng_, texel_size_m));
    w.radius = BodyRadius(looks_.back());
    // Evenly spread over the walkers, without random draws (other walkers keep theirs).
    const double f = o.non_yielding_fraction;
    w.yields = !(std::floor((i + 1) * f) > std::floor(i * f));
    w.preferred_speed = std::max(0.3f, static_cast<float>(std::normal_distribution<double>(
                                           o.speed_mps, o.speed_stddev_mps)(rng_)));
    // Crossing walkers start around the robot's first few metres, the others anywhere.
    const bool near_robot =
        robot && UniformF(rng_, 0.0f, 1.0f) < o.crossing_fraction &&
        SpotAheadOfRobot(o, scene_, View(robot->base, view_yaw_rad_),
                         UniformF(rng_, 0.0f, 1.0f) < 0.5f ? 1.0f : -1.0f, w.radius, rng_, &w.p);
    if (!near_robot) w.p = RandomFreeSpot(scene_, w.radius, rng_);
    if (robot) KeepClearOfRobot(o, *robot, w.yields, w.radius, &w.p);
    w.phase = UniformF(rng_, 0.0f, 2.0f * static_cast<float>(M_PI));
    ChooseGoal(robot, &w);
    const Vec2f dir = w.goal - w.p;
    w.heading = std::atan2(dir.y(), dir.x());
  }
}

void CrowdStepper::ChooseGoal(const std::optional<CrowdRobot>& robot, Walker* w) {
  const CrowdOptions& o = options_;
  w->stuck_s = 0.0f;
  if (UniformF(rng_, 0.0f, 1.0f) < o.crossing_fraction && robot) {
    // Aim at the far side of where the robot will be soon, so the walk crosses its view.
    const PlanarPose r = View(robot->base_ahead, view_yaw_rad_);
    const Vec2f left(-std::sin(r.yaw_rad), std::cos(r.yaw_rad));
    const float lateral = (w->p - Vec2f(r.x_m, r.y_m)).dot(left);
    if (SpotAheadOfRobot(o, scene_, r, lateral >= 0.0f ? -1.0f : 1.0f, w->radius, rng_, &w->goal)) {
      return;
    }
  }
  w->goal = RandomFreeSpot(scene_, w->radius, rng_);
}

void CrowdStepper::MoveWalker(const CrowdRobot& robot, size_t self, float dt) {
  const CrowdOptions& o = options_;
  Walker* w = &walkers_[self];
  const Vec2f to_goal = w->goal - w->p;
  const float dist = to_goal.norm();
  Vec2f vel = dist > 1e-3f ? Vec2f(to_goal / dist * w->preferred_speed) : Vec2f::Zero();
  // Repulsion from furniture, walls, other walkers and the robot (social-force style).
  Vec2f away;
  for (const BoxPrimitive& b : scene_.boxes) {
    const float d = DistanceToFootprint(b, w->p, &away);
    if (d < w->radius + 0.5f) vel += away * 2.0f * (w->radius + 0.5f - d);
  }
  const float wall = w->radius + 0.5f;
  vel.x() += 2.0f * (std::max(0.0f, wall - w->p.x()) -
                     std::max(0.0f, w->p.x() - (scene_.room.width_m - wall)));
  vel.y() += 2.0f * (std::max(0.0f, wall - w->p.y()) -
                     std::max(0.0f, w->p.y() - (scene_.room.length_m - wall)));
  for (size_t j = 0; j < walkers_.size(); ++j) {
    if (j == self) continue;
    const Vec2f diff = w->p - walkers_[j].p;
    const float d = diff.norm(), reach = w->radius + walkers_[j].radius + 0.3f;
    if (d < reach && d > 1e-4f) vel += diff / d * 1.5f * (reach - d) / 0.3f;
  }
  const Vec2f r(robot.base.x_m, robot.base.y_m);
  const float keep_out = static_cast<float>(o.robot_clearance_m) + w->radius;
  if (w->yields) {
    const Vec2f diff = w->p - r;
    const float d = diff.norm();
    if (d < keep_out + 1.0f && d > 1e-4f) vel += diff / d * 2.0f * (keep_out + 1.0f - d);
  }
  const float max_speed = 1.5f * w->preferred_speed + 0.2f;
  if (vel.norm() > max_speed) vel *= max_speed / vel.norm();
  Vec2f next = w->p + vel * dt;
  if (!FreeSpot(scene_, next, w->radius)) next = w->p;
  if (SeesTheRobotsBody(robot, w->yields)) {
    StepAroundRobotBody(o, robot, w->radius, w->p, &next);
  } else {
    KeepClearOfRobot(o, robot, w->yields, w->radius, &next);
  }
  const float moved = (next - w->p).norm();
  const float progress = dist - (w->goal - next).norm();
  w->stuck_s =
      progress < 0.2f * w->preferred_speed * dt ? w->stuck_s + dt : std::max(0.0f, w->stuck_s - dt);
  const float speed = moved / dt;
  if (speed > 0.05f) {
    const Vec2f dir = (next - w->p) / moved;
    const float delta = std::remainder(std::atan2(dir.y(), dir.x()) - w->heading, 2.0f * M_PI);
    w->heading += std::clamp(delta, -kMaxTurnRadPerS * dt, kMaxTurnRadPerS * dt);
  }
  w->phase = std::fmod(w->phase + 2.0f * static_cast<float>(M_PI) * moved / kStrideCycleM,
                       2.0f * static_cast<float>(M_PI));
  w->swing = 0.18f * std::min(1.0f, speed / 1.2f);
  w->p = next;
}

void CrowdStepper::Step(const CrowdRobot& robot, double dt_s) {
  // Sub-steps keep the avoidance stable at low frame rates.
  const int substeps = std::max(1, static_cast<int>(std::ceil(dt_s / 0.05)));
  const float dt = static_cast<float>(dt_s / substeps);
  for (int s = 0; s < substeps; ++s) {
    for (size_t i = 0; i < walkers_.size(); ++i) {
      Walker& w = walkers_[i];
      if ((w.goal - w.p).norm() < 0.5f || w.stuck_s > 4.0f) ChooseGoal(robot, &w);
      MoveWalker(robot, i, dt);
    }
  }
}

std::vector<PedestrianState> CrowdStepper::States() const {
  std::vector<PedestrianState> out;
  out.reserve(walkers_.size());
  for (const Walker& w : walkers_) {
    PedestrianState st;
    st.x_m = w.p.x();
    st.y_m = w.p.y();
    st.heading_rad = w.heading;
    st.gait_phase_rad = w.phase;
    st.swing_m = w.swing;
    out.push_back(st);
  }
  return out;
}

void CrowdStepper::AppendBodyParts(std::vector<CylinderPrimitive>* out) const {
  const std::vector<PedestrianState> states = States();
  for (size_t i = 0; i < looks_.size(); ++i) sim::AppendBodyParts(looks_[i], states[i], out);
}

}  // namespace icgm::sim
