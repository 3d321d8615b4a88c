#include "core/map/semi_consensus.h"

#include <cassert>

#include "core/map/se3_geodesic.h"

namespace icgm {

std::vector<Pose3> SemiConsensusCorrection(const Pose3& pose_a,
                                           const std::vector<Pose3>& relative_poses,
                                           const Pose3& loop_closure_pose, double alpha) {
  assert(!relative_poses.empty());
  std::vector<Pose3> chain;  // L_a .. L_b, uncorrected
  chain.reserve(relative_poses.size() + 1);
  chain.push_back(pose_a);
  for (const auto& r : relative_poses) chain.push_back(Compose(chain.back(), r));
  const Pose3 world_difference = loop_closure_pose * chain.back().inverse();
  const double n = static_cast<double>(relative_poses.size());
  const Pose3 increment = GeodesicExp(alpha / n * GeodesicLog(world_difference));
  std::vector<Pose3> corrected;
  corrected.reserve(relative_poses.size());
  for (size_t k = 0; k < relative_poses.size(); ++k) {
    const Pose3& previous = chain[k];
    corrected.push_back(
        Orthonormalized(previous.inverse() * increment * previous * relative_poses[k]));
  }
  return corrected;
}

}  // namespace icgm
