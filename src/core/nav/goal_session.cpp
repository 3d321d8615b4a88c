#include "core/nav/goal_session.h"

#include <cmath>
#include <cstdio>
#include <exception>
#include <utility>

#include "core/map/map_store.h"

namespace icgm {

GoalSession::GoalSession(NavigationOptions options, double pose_wait_s)
    : navigator_(std::move(options)), pose_wait_s_(pose_wait_s) {}

Status GoalSession::LoadMap(const std::string& path) {
  Cancel();
  map_set_ = false;
  map_ = HybridMap();
  try {
    if (path.empty()) throw LoadError("no map path set");
    map_ = icgm::LoadMap(path, &map_note_);
    if (map_.empty()) throw LoadError("map '" + path + "' has no keyframes");
    map_error_.clear();
    return Status::Ok();
  } catch (const std::exception& e) {
    map_error_ = std::string("no map: ") + e.what();
    return Status::Error(map_error_);
  }
}

Status GoalSession::Accept(double wall_s) {
  Cancel();
  if (!has_map()) return Status::Error(map_error_);
  pending_ = true;
  received_wall_s_ = wall_s;
  return Status::Ok();
}

void GoalSession::Cancel() {
  pending_ = driving_ = false;
  navigator_.Cancel();
}

GoalCycle GoalSession::End(GoalCycleResult result, std::string text) {
  Cancel();
  GoalCycle c;
  c.result = result;
  c.text = std::move(text);
  return c;
}

// Starts the pending goal once the pose, the goal's position and the extrinsic are known; gives
// up after pose_wait_s.
GoalCycle GoalSession::Start(const GoalCycleInputs& in) {
  Status s = in.T_map_base ? in.goal_status : Status::Error(in.pose_error);
  if (s.ok() && !in.T_base_camera) s = Status::Error(in.extrinsic_error);
  if (!s.ok()) {
    if (in.wall_s - received_wall_s_ > pose_wait_s_) return End(GoalCycleResult::kAborted, s.reason());
    return GoalCycle{GoalCycleResult::kWaiting, s.reason(), VelocityCommand()};
  }
  if (!map_set_) s = navigator_.SetMap(map_, *in.T_base_camera);
  map_set_ = s.ok();
  if (s.ok()) s = navigator_.SetGoal(in.goal_m, *in.T_map_base, in.goal_yaw_rad);
  if (!s.ok()) return End(GoalCycleResult::kAborted, s.reason());
  pending_ = false;
  driving_ = true;
  char text[96];
  std::snprintf(text, sizeof(text), "goal (%.2f, %.2f): route of %zu nodes", in.goal_m.x(),
                in.goal_m.y(), navigator_.route_nodes().size());
  return GoalCycle{GoalCycleResult::kStarted, text, VelocityCommand()};
}

GoalCycle GoalSession::Cycle(const GoalCycleInputs& in) {
  if (pending_) return Start(in);
  if (!driving_) return GoalCycle();
  const NavigationStatus s = navigator_.Update(in.now, in.dt_s);
  if (s.state == NavigationState::kReached) {
    char text[96];
    std::snprintf(text, sizeof(text), "reached: %.3f m from the goal", s.distance_to_goal_m);
    std::string result = text;
    if (s.goal_yaw_error_rad != 0.0) {  // the goal's orientation was driven to
      std::snprintf(text, sizeof(text), ", %.1f deg from its yaw",
                    std::abs(s.goal_yaw_error_rad) * 180.0 / M_PI);
      result += text;
    }
    // An occupied goal reached within navigator.goal_occupied_tolerance_m says so.
    if (!s.reason.empty()) result += " (" + s.reason + ")";
    return End(GoalCycleResult::kSucceeded, result);
  }
  if (s.state == NavigationState::kAborted) return End(GoalCycleResult::kAborted, s.reason);
  return GoalCycle{GoalCycleResult::kDriving, s.reason, s.command};
}

}  // namespace icgm
