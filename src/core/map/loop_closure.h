// Loop-closure detection of thesis 6.1.1.2 (Fig. 6.3):
//  1. dictionary scores of the current model against all earlier models (visual_dictionary.h);
//  2. the `candidates_per_loop` (3) best-scored models of every earlier learned loop (the own
//     loop counts too, without its `exclude_recent_keyframes` latest models);
//  3. 6D registration of the current model to each candidate through RegisterFn (RegisterRgbd in
//     the system, a synthetic function in tests); a loop fails when all its candidates fail;
//  4. per loop the best relative pose beta_i (most inliers) gives L_loop_i = L_li (+) beta_i;
//  5. (ours, not in the thesis, which always trusts L_LoopClosure) false-loop guard: each
//     L_loop_i must lie within `gate_sigma` standard deviations of the current own-loop pose
//     L_Current, where the deviation grows with the path travelled since the last correction,
//     and hypotheses must agree with each other within `agreement_m/_rad`; a very large
//     gate_sigma and agreement (config/thesis/map.yaml) give the thesis's detection;
//  6. the pose-set optimization of eq. 6.2 (pose_average.h) gives L_LoopClosure, and eq. 6.3
//     DeltaPose_Diff = L_LoopClosure (-) L_Current.
// Beyond the thesis (both off by default in this struct):
//  - proximity candidates: the `proximity_candidates` earlier models nearest to L_Current (within
//    proximity_radius_m / _rad), one per earlier pass of the place, are registered too, when the
//    dictionary did not propose them (or a model of the same pass).
//    Each verified one is its own hypothesis (and loop link), so a revisit can be linked to
//    several earlier models, e.g. the last keyframes of a session to its first ones, whose
//    dictionary score suffers from walkers or little texture. They pass the same guard (5);
//    eq. 6.2 still takes one hypothesis per loop (the one with most inliers).
//  - a loop link must join models at the same place: a registration whose beta moves farther
//    than max_link_translation_m / max_link_rad is not a loop closure.
// The correction itself (eq. 6.4) is applied by HybridMap::ApplySemiConsensus.
#pragma once

#include <functional>
#include <set>
#include <string>
#include <utility>
#include <vector>

#include "core/common/enum_names.h"
#include "core/common/pose.h"
#include "core/common/status.h"
#include "core/map/hybrid_map.h"
#include "core/map/keyframe.h"
#include "core/map/visual_dictionary.h"

namespace icgm {

// Result of registering the current model (query) to an earlier one (candidate).
struct RegistrationOutcome {
  Status status = Status::Error("registration not run");
  Pose3 relative_pose = Pose3::Identity();  // beta: query in the candidate's frame
  int inliers = 0;
  Mat6 information = Mat6::Identity();  // of relative_pose, twist layout of se3_geodesic.h
  // Keypoint index pairs (query, candidate) of the inliers, when the registration reports them
  // (KeyframeRegistration does; the map's bundle adjustment builds its point tracks from them).
  std::vector<std::pair<int, int>> inlier_matches;
};
// RegisterRgbd plugs in with ref = candidate, cur = query (its relative_pose is "cur in ref").
using RegisterFn =
    std::function<RegistrationOutcome(const Keyframe& query, const Keyframe& candidate)>;

// Correction after a loop closure (`loop_closure.correction`): eq. 6.4's semi-consensus or a
// pose-graph optimization of the whole map.
enum class LoopCorrection { kSemiConsensus, kPoseGraph };

template <>
struct EnumNames<LoopCorrection> {
  static constexpr EnumName<LoopCorrection> kNames[] = {
      {LoopCorrection::kSemiConsensus, "semi_consensus"},
      {LoopCorrection::kPoseGraph, "pose_graph"}};
};

struct LoopClosureOptions {
  int candidates_per_loop = 3;
  int max_loops = 8;                  // earlier loops tried, best dictionary score first
  double min_score = 0.05;            // dictionary score below which a model is not a candidate
  int exclude_recent_keyframes = 20;  // own-loop models this recent are not candidates
  int min_inliers = 20;               // geometric verification
  // Own-loop pose uncertainty: sigma = base + per_m * path length since the last correction.
  double sigma_base_m = 0.3;
  double sigma_per_m = 0.1;
  double sigma_base_rad = 0.1;
  double sigma_per_m_rad = 0.02;
  double gate_sigma = 3.0;
  double agreement_m = 0.5;  // hypotheses of different loops must agree this well
  double agreement_rad = 0.2;
  double alpha_mapping = 0.5;       // eq. 6.4 while mapping, 0 < alpha < 1
  double alpha_localization = 1.0;  // while localizing / navigating (thesis 6.1.2)
  // Correction after a loop closure: semi_consensus (eq. 6.4, the thesis) or pose_graph
  // (optimize the whole graph, PoseGraphOptimizer; alpha is then unused).
  LoopCorrection correction = LoopCorrection::kSemiConsensus;
  // Proximity candidates (0: off, the thesis's dictionary-only detection).
  int proximity_candidates = 0;
  double proximity_radius_m = 0.5;
  double proximity_radius_rad = 0.52;
  // Candidates closer than this many keyframe ids to a chosen or dictionary-proposed one are
  // the same pass of the place and skipped (one proximity candidate per pass).
  int proximity_separation = 20;
  // Start candidates (0: off): the current session's first this many models are registered
  // too, each verified one a further loop link.
  int start_candidates = 0;
  // Geometric verification of a start candidate's registration (0: min_inliers). The first
  // models saw the place before a crowd filled the view: a revisit finds fewer of their points
  // than a loop among crowded models does.
  int start_min_inliers = 0;
  // Own-session models this recent are not start candidates (-1: exclude_recent_keyframes).
  // Where walkers make nearly every frame a keyframe, the 20 keyframes after the start span the
  // first second or two, the stretch where a hand-held camera's drift is made.
  int start_exclude_recent_keyframes = -1;
  // Largest |beta| of a loop link (translation, rotation angle): a loop link joins keyframes at
  // the same place, so a larger registered motion is a wrong match, not a loop closure.
  double max_link_translation_m = 0.45;
  double max_link_rad = 0.5;
};

struct LoopEvidence {
  int loop_id = -1;
  int candidate_id = -1;
  double score = 0.0;  // dictionary score (0 for a proximity candidate it did not propose)
  bool proximity = false;  // proposed by the proximity search, not the dictionary
  bool start = false;      // one of the session's first models (start_candidates)
  RegistrationOutcome registration;
  Pose3 global_pose = Pose3::Identity();  // L_loop_i = L_li (+) beta_i
  std::string rejected;                   // empty when used in eq. 6.2
};

struct LoopClosureResult {
  Status status = Status::Error("no loop closure");
  Pose3 loop_closure_pose = Pose3::Identity();  // L_LoopClosure (eq. 6.2)
  Pose3 delta_pose_diff = Pose3::Identity();    // eq. 6.3, in L_Current's frame
  // One per loop with a registered dictionary candidate, plus one per registered proximity
  // candidate.
  std::vector<LoopEvidence> evidence;
  int registrations = 0;
};

// The evidence of one registered candidate: its loop and id, the dictionary score, the
// registration and the query's global pose it implies (L_loop_i = L_li (+) beta_i).
LoopEvidence MakeLoopEvidence(const Keyframe& candidate, double score,
                              const RegistrationOutcome& outcome);

// Step 5 (a): why `located` lies too far from the query's pose `predicted` for the pose
// uncertainty after `path_since_correction_m` metres without a correction ("jump ..." or
// "turn ..."); empty when it lies within gate_sigma sigmas.
std::string PoseGateRejection(const Pose3& predicted, const Pose3& located,
                              double path_since_correction_m, const LoopClosureOptions& o);

class LoopClosureDetector {
 public:
  explicit LoopClosureDetector(const LoopClosureOptions& options) : options_(options) {}

  // `query` is the current model, not yet in `map`, with global_pose = L_Current (eq. 6.1).
  // `path_since_correction_m` scales the own-loop pose uncertainty of the guard.
  LoopClosureResult Detect(const Keyframe& query, const std::vector<DictionaryMatch>& scores,
                           const HybridMap& map, const RegisterFn& register_fn,
                           double path_since_correction_m) const;

  const LoopClosureOptions& options() const { return options_; }

 private:
  // Registers the proximity candidates (see the header comment) and appends the verified ones
  // to result->evidence; `proposed` are the dictionary's candidates, `linked` the candidates
  // with a verified registration so far (extended here).
  void AddProximityEvidence(const Keyframe& query, const HybridMap& map,
                            const RegisterFn& register_fn, const std::set<int>& proposed,
                            std::vector<int>* linked, LoopClosureResult* result) const;

  // Registers the session's first `start_candidates` models (see the header comment) that are
  // not recent, proposed or linked, and appends the verified ones to result->evidence.
  void AddStartEvidence(const Keyframe& query, const HybridMap& map, const RegisterFn& register_fn,
                        const std::set<int>& proposed, std::vector<int>* linked,
                        LoopClosureResult* result) const;

  LoopClosureOptions options_;
};

}  // namespace icgm
