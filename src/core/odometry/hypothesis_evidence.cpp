#include "core/odometry/hypothesis_evidence.h"

#include <algorithm>

namespace icgm {

std::vector<double> EvidenceScores(const std::vector<HypothesisEvidence>& hypotheses,
                                   bool normalized) {
  std::vector<double> scores;
  scores.reserve(hypotheses.size());
  if (!normalized) {
    for (const HypothesisEvidence& h : hypotheses) {
      scores.push_back(static_cast<double>(h.depth_agreeing + h.edges_agreeing));
    }
    return scores;
  }
  size_t max_depth = 0, max_edges = 0;
  for (const HypothesisEvidence& h : hypotheses) {
    max_depth = std::max(max_depth, h.depth_agreeing);
    max_edges = std::max(max_edges, h.edges_agreeing);
  }
  // A cue no hypothesis has (e.g. no grey image: no edges) adds nothing.
  const auto share = [](size_t n, size_t max) {
    return max > 0 ? static_cast<double>(n) / static_cast<double>(max) : 0.0;
  };
  for (const HypothesisEvidence& h : hypotheses) {
    scores.push_back(share(h.depth_agreeing, max_depth) + share(h.edges_agreeing, max_edges));
  }
  return scores;
}

const char* HypothesisKindName(HypothesisKind kind) {
  switch (kind) {
    case HypothesisKind::kIcgm:
      return "icgm";
    case HypothesisKind::kLeftOut:
      return "left_out";
    case HypothesisKind::kPrediction:
      return "prediction";
    case HypothesisKind::kMap:
      return "map";
    case HypothesisKind::kSeed:
      return "seed";
  }
  return "unknown";
}

}  // namespace icgm
