#include "core/map/loop_closure.h"

#include <algorithm>
#include <map>
#include <sstream>

#include "core/map/pose_average.h"

namespace icgm {
namespace {

std::string Format(const char* what, double value, double limit, const char* unit) {
  std::ostringstream s;
  s.precision(3);
  s << what << " " << value << unit << " > " << limit << unit;
  return s.str();
}

}  // namespace

LoopClosureResult LoopClosureDetector::Detect(const Keyframe& query,
                                              const std::vector<DictionaryMatch>& scores,
                                              const HybridMap& map, const RegisterFn& register_fn,
                                              double path_since_correction_m) const {
  LoopClosureResult result;
  const int latest = map.LatestInSession();
  // Step 2: best-scored candidates per learned loop (scores arrive best first).
  std::map<int, std::vector<DictionaryMatch>> per_loop;
  std::vector<int> loop_order;
  for (const auto& m : scores) {
    if (m.score < options_.min_score) break;
    if (m.keyframe_id < 0 || m.keyframe_id >= map.size()) continue;
    const Keyframe& kf = map.keyframe(m.keyframe_id);
    if (kf.session_id == map.current_session() && latest >= 0 &&
        latest - kf.id < options_.exclude_recent_keyframes) {
      continue;
    }
    auto& list = per_loop[kf.loop_id];
    if (list.empty()) {
      if (static_cast<int>(loop_order.size()) >= options_.max_loops) continue;
      loop_order.push_back(kf.loop_id);
    }
    if (static_cast<int>(list.size()) < options_.candidates_per_loop) list.push_back(m);
  }
  if (loop_order.empty()) {
    result.status = Status::Error("no loop closure: no candidate scored >= min_score");
    return result;
  }
  // Steps 3-4: register to each candidate, keep the best beta per loop.
  for (int loop_id : loop_order) {
    LoopEvidence best;
    for (const auto& m : per_loop[loop_id]) {
      const Keyframe& candidate = map.keyframe(m.keyframe_id);
      RegistrationOutcome outcome = register_fn(query, candidate);
      ++result.registrations;
      if (!outcome.status.ok() || outcome.inliers < options_.min_inliers) continue;
      if (best.candidate_id < 0 || outcome.inliers > best.registration.inliers) {
        best.loop_id = loop_id;
        best.candidate_id = m.keyframe_id;
        best.score = m.score;
        best.registration = outcome;
        best.global_pose = Orthonormalized(Compose(candidate.global_pose, outcome.relative_pose));
      }
    }
    if (best.candidate_id >= 0) result.evidence.push_back(best);
  }
  if (result.evidence.empty()) {
    result.status = Status::Error("no loop closure: registration failed for all " +
                                  std::to_string(result.registrations) + " candidates");
    return result;
  }
  // Step 5a: consistency with the current pose uncertainty.
  const double sigma_m = options_.sigma_base_m + options_.sigma_per_m * path_since_correction_m;
  const double sigma_rad =
      options_.sigma_base_rad + options_.sigma_per_m_rad * path_since_correction_m;
  std::vector<LoopEvidence*> accepted;
  for (auto& e : result.evidence) {
    const Pose3 diff = Between(query.global_pose, e.global_pose);
    if (TranslationNorm(diff) > options_.gate_sigma * sigma_m) {
      e.rejected = Format("jump", TranslationNorm(diff), options_.gate_sigma * sigma_m, " m");
    } else if (RotationAngleRad(diff) > options_.gate_sigma * sigma_rad) {
      e.rejected = Format("turn", RotationAngleRad(diff), options_.gate_sigma * sigma_rad, " rad");
    } else {
      accepted.push_back(&e);
    }
  }
  // Step 5b: hypotheses of different loops must agree; keep the largest agreeing group.
  std::vector<LoopEvidence*> group;
  for (LoopEvidence* seed : accepted) {
    std::vector<LoopEvidence*> members;
    for (LoopEvidence* other : accepted) {
      const Pose3 d = Between(seed->global_pose, other->global_pose);
      if (TranslationNorm(d) <= options_.agreement_m &&
          RotationAngleRad(d) <= options_.agreement_rad) {
        members.push_back(other);
      }
    }
    if (members.size() > group.size()) group = members;
  }
  for (LoopEvidence* e : accepted) {
    if (std::find(group.begin(), group.end(), e) == group.end()) {
      e->rejected = "disagrees with the other loops";
    }
  }
  if (group.empty()) {
    result.status = Status::Error("loop closure rejected: " + result.evidence.front().rejected +
                                  " from the own-loop pose (uncertainty guard)");
    return result;
  }
  // Step 6: eq. 6.2 and eq. 6.3.
  std::vector<WeightedPose> hypotheses;
  for (const LoopEvidence* e : group)
    hypotheses.push_back({e->global_pose, e->registration.information});
  const Status averaged = AveragePoses(hypotheses, &result.loop_closure_pose);
  if (!averaged.ok()) {
    result.status = Status::Error("loop closure rejected: " + averaged.reason());
    return result;
  }
  result.delta_pose_diff = Between(query.global_pose, result.loop_closure_pose);
  result.status = Status::Ok();
  return result;
}

}  // namespace icgm
