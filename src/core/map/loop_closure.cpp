#include "core/map/loop_closure.h"

#include <algorithm>
#include <cstdlib>
#include <map>
#include <set>
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

// Own-session models less than `exclude` keyframes old are not loop candidates.
bool Recent(const Keyframe& kf, const HybridMap& map, int exclude) {
  const int latest = map.LatestInSession();
  return kf.session_id == map.current_session() && latest >= 0 && latest - kf.id < exclude;
}

bool Recent(const Keyframe& kf, const HybridMap& map, const LoopClosureOptions& o) {
  return Recent(kf, map, o.exclude_recent_keyframes);
}

// Geometric verification of a loop-closure registration with at least `min_inliers`.
bool Verified(const RegistrationOutcome& outcome, int min_inliers, const LoopClosureOptions& o) {
  return outcome.status.ok() && outcome.inliers >= min_inliers &&
         TranslationNorm(outcome.relative_pose) <= o.max_link_translation_m &&
         RotationAngleRad(outcome.relative_pose) <= o.max_link_rad;
}

}  // namespace

LoopEvidence MakeLoopEvidence(const Keyframe& candidate, double score,
                              const RegistrationOutcome& outcome) {
  LoopEvidence e;
  e.loop_id = candidate.loop_id;
  e.candidate_id = candidate.id;
  e.score = score;
  e.registration = outcome;
  e.global_pose = Orthonormalized(Compose(candidate.global_pose, outcome.relative_pose));
  return e;
}

std::string PoseGateRejection(const Pose3& predicted, const Pose3& located,
                              double path_since_correction_m, const LoopClosureOptions& o) {
  const double sigma_m = o.sigma_base_m + o.sigma_per_m * path_since_correction_m;
  const double sigma_rad = o.sigma_base_rad + o.sigma_per_m_rad * path_since_correction_m;
  const Pose3 diff = Between(predicted, located);
  if (TranslationNorm(diff) > o.gate_sigma * sigma_m) {
    return Format("jump", TranslationNorm(diff), o.gate_sigma * sigma_m, " m");
  }
  if (RotationAngleRad(diff) > o.gate_sigma * sigma_rad) {
    return Format("turn", RotationAngleRad(diff), o.gate_sigma * sigma_rad, " rad");
  }
  return "";
}

void LoopClosureDetector::AddProximityEvidence(const Keyframe& query, const HybridMap& map,
                                               const RegisterFn& register_fn,
                                               const std::set<int>& proposed,
                                               std::vector<int>* linked,
                                               LoopClosureResult* result) const {
  if (options_.proximity_candidates <= 0) return;
  // Earlier models near L_Current, nearest first (distance in units of the search radius).
  std::vector<std::pair<double, int>> near;
  for (const Keyframe& kf : map.keyframes()) {
    if (Recent(kf, map, options_) || proposed.count(kf.id) ||
        static_cast<int>(kf.keypoints.size()) < options_.min_inliers) {
      continue;
    }
    const Pose3 d = Between(query.global_pose, kf.global_pose);
    const double t = TranslationNorm(d) / options_.proximity_radius_m;
    const double r = RotationAngleRad(d) / options_.proximity_radius_rad;
    if (t <= 1.0 && r <= 1.0) near.emplace_back(t + r, kf.id);
  }
  std::sort(near.begin(), near.end());
  // One link per earlier pass: a model within proximity_separation ids of a linked one views
  // the place from the same pass; a failed registration lets the next model of its pass try.
  int attempts = 0;
  for (const auto& [distance, id] : near) {
    if (attempts >= options_.proximity_candidates) break;
    const bool same_pass = std::any_of(linked->begin(), linked->end(), [&, id = id](int other) {
      return std::abs(other - id) < options_.proximity_separation;
    });
    if (same_pass) continue;
    const Keyframe& candidate = map.keyframe(id);
    const RegistrationOutcome outcome = register_fn(query, candidate);
    ++attempts;
    ++result->registrations;
    if (!Verified(outcome, options_.min_inliers, options_)) continue;
    result->evidence.push_back(MakeLoopEvidence(candidate, 0.0, outcome));
    result->evidence.back().proximity = true;
    linked->push_back(id);
  }
}

void LoopClosureDetector::AddStartEvidence(const Keyframe& query, const HybridMap& map,
                                           const RegisterFn& register_fn,
                                           const std::set<int>& proposed, std::vector<int>* linked,
                                           LoopClosureResult* result) const {
  if (options_.start_candidates <= 0) return;
  const int min_inliers =
      options_.start_min_inliers > 0 ? options_.start_min_inliers : options_.min_inliers;
  const int exclude = options_.start_exclude_recent_keyframes >= 0
                          ? options_.start_exclude_recent_keyframes
                          : options_.exclude_recent_keyframes;
  int taken = 0;
  for (const Keyframe& kf : map.keyframes()) {
    if (kf.session_id != map.current_session()) continue;
    if (taken++ >= options_.start_candidates) break;
    if (Recent(kf, map, exclude) || proposed.count(kf.id) ||
        std::find(linked->begin(), linked->end(), kf.id) != linked->end() ||
        static_cast<int>(kf.keypoints.size()) < min_inliers) {
      continue;
    }
    const RegistrationOutcome outcome = register_fn(query, kf);
    ++result->registrations;
    if (!Verified(outcome, min_inliers, options_)) continue;
    result->evidence.push_back(MakeLoopEvidence(kf, 0.0, outcome));
    result->evidence.back().start = true;
    linked->push_back(kf.id);
  }
}

LoopClosureResult LoopClosureDetector::Detect(const Keyframe& query,
                                              const std::vector<DictionaryMatch>& scores,
                                              const HybridMap& map, const RegisterFn& register_fn,
                                              double path_since_correction_m) const {
  LoopClosureResult result;
  // Step 2: best-scored candidates per learned loop (scores arrive best first).
  std::map<int, std::vector<DictionaryMatch>> per_loop;
  std::vector<int> loop_order;
  std::set<int> proposed;
  for (const auto& m : scores) {
    if (m.score < options_.min_score) break;
    if (m.keyframe_id < 0 || m.keyframe_id >= map.size()) continue;
    const Keyframe& kf = map.keyframe(m.keyframe_id);
    if (Recent(kf, map, options_)) continue;
    auto& list = per_loop[kf.loop_id];
    if (list.empty()) {
      if (static_cast<int>(loop_order.size()) >= options_.max_loops) continue;
      loop_order.push_back(kf.loop_id);
    }
    if (static_cast<int>(list.size()) < options_.candidates_per_loop) {
      list.push_back(m);
      proposed.insert(m.keyframe_id);
    }
  }
  if (loop_order.empty() && options_.proximity_candidates <= 0 && options_.start_candidates <= 0) {
    result.status = Status::Error("no loop closure: no candidate scored >= min_score");
    return result;
  }
  // Steps 3-4: register to each candidate, keep the best beta per loop.
  std::vector<int> linked;  // candidates with a verified registration
  for (int loop_id : loop_order) {
    LoopEvidence best;
    for (const auto& m : per_loop[loop_id]) {
      const Keyframe& candidate = map.keyframe(m.keyframe_id);
      RegistrationOutcome outcome = register_fn(query, candidate);
      ++result.registrations;
      if (!Verified(outcome, options_.min_inliers, options_)) continue;
      linked.push_back(m.keyframe_id);
      if (best.candidate_id < 0 || outcome.inliers > best.registration.inliers) {
        best = MakeLoopEvidence(candidate, m.score, outcome);
      }
    }
    if (best.candidate_id >= 0) result.evidence.push_back(best);
  }
  AddStartEvidence(query, map, register_fn, proposed, &linked, &result);
  AddProximityEvidence(query, map, register_fn, proposed, &linked, &result);
  if (result.evidence.empty()) {
    result.status = Status::Error(
        result.registrations == 0
            ? "no loop closure: no candidate scored >= min_score or lay near the current pose"
            : "no loop closure: registration failed for all " +
                  std::to_string(result.registrations) + " candidates");
    return result;
  }
  // Step 5a: consistency with the current pose uncertainty.
  std::vector<LoopEvidence*> accepted;
  for (auto& e : result.evidence) {
    e.rejected =
        PoseGateRejection(query.global_pose, e.global_pose, path_since_correction_m, options_);
    if (e.rejected.empty()) accepted.push_back(&e);
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
  // Step 6: eq. 6.2 over one hypothesis per loop (most inliers), and eq. 6.3.
  std::map<int, const LoopEvidence*> per_loop_best;
  for (const LoopEvidence* e : group) {
    const LoopEvidence*& best = per_loop_best[e->loop_id];
    if (!best || e->registration.inliers > best->registration.inliers) best = e;
  }
  std::vector<WeightedPose> hypotheses;
  for (const LoopEvidence* e : group) {
    if (per_loop_best[e->loop_id] == e)
      hypotheses.push_back({e->global_pose, e->registration.information});
  }
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
