// Navigation along the longest learned loop (thesis 6.1.2). The models of the longest loop are
// indexed 0 .. N-1 (the thesis counts 1 .. N); a pointer p marks where the robot is. Each cycle
// the current model is matched to model i of that loop (loop closure, with RelPose_current = the
// current model's pose in M_i; when loop closure fails, i is the best dictionary match and
// RelPose_current = identity), and the robot moves by eq. 6.5
//   Pos_Move = L_(i+omega) (-) L_i (+) RelPose_current
// toward model i + omega, after which p = i + omega. Here (+)/(-) are read so that the motion is
// exact: the robot stands at L_i * RelPose, so in its own frame the motion to L_(i+omega) is
//   Pos_Move = RelPose^-1 * (L_i^-1 * L_(i+omega)),
// which equals the thesis's expression when RelPose_current = identity.
#pragma once

#include <vector>

#include "core/common/pose.h"
#include "core/common/status.h"
#include "core/map/hybrid_map.h"

namespace icgm {

class LoopFollower {
 public:
  // `loop_poses` = L of the loop's models in order; `omega` >= 1 is the logical step.
  LoopFollower(std::vector<Pose3> loop_poses, int omega);
  // Keyframe ids of the map's loop with the most keyframes (empty map: empty).
  static std::vector<int> LongestLoop(const HybridMap& map);
  static LoopFollower FromLongestLoop(const HybridMap& map, int omega);

  // Eq. 6.5 for a match at index `matched_index`; the target index is clamped to N-1. Advances
  // the pointer. Fails for an index outside the loop or when already at the end.
  Status Step(int matched_index, const Pose3& rel_pose_current, Pose3* pos_move);

  int pointer() const { return pointer_; }
  int size() const { return static_cast<int>(poses_.size()); }
  bool done() const { return pointer_ >= size() - 1; }

 private:
  std::vector<Pose3> poses_;
  int omega_;
  int pointer_ = 0;
};

}  // namespace icgm
