#include "core/nav/loop_follower.h"

#include <algorithm>
#include <string>

namespace icgm {

LoopFollower::LoopFollower(std::vector<Pose3> loop_poses, int omega)
    : poses_(std::move(loop_poses)), omega_(std::max(1, omega)) {}

std::vector<int> LoopFollower::LongestLoop(const HybridMap& map) {
  const LoopRecord* best = nullptr;
  for (const auto& loop : map.loops()) {
    if (!best || loop.keyframe_ids.size() > best->keyframe_ids.size()) best = &loop;
  }
  return best ? best->keyframe_ids : std::vector<int>{};
}

LoopFollower LoopFollower::FromLongestLoop(const HybridMap& map, int omega) {
  std::vector<Pose3> poses;
  for (int id : LongestLoop(map)) poses.push_back(map.keyframe(id).global_pose);
  return LoopFollower(std::move(poses), omega);
}

Status LoopFollower::Step(int matched_index, const Pose3& rel_pose_current, Pose3* pos_move) {
  if (matched_index < 0 || matched_index >= size()) {
    return Status::Error("navigation: matched model " + std::to_string(matched_index) +
                         " is not in the loop of " + std::to_string(size()) + " models");
  }
  if (done()) return Status::Error("navigation: goal already reached");
  const int target = std::min(matched_index + omega_, size() - 1);
  *pos_move = rel_pose_current.inverse() * Between(poses_[matched_index], poses_[target]);
  pointer_ = target;
  return Status::Ok();
}

}  // namespace icgm
