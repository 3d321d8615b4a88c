#include "core/odometry/hypothesis_evidence.h"

#include <algorithm>
#include <cstdint>

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

size_t SpreadCells(const std::vector<cv::Point2f>& px, cv::Size image, int cols, int rows) {
  if (image.width <= 0 || image.height <= 0 || cols <= 0 || rows <= 0) return 0;
  std::vector<uint8_t> held(static_cast<size_t>(cols) * rows, 0);
  for (const cv::Point2f& p : px) {
    if (!(p.x >= 0.0f && p.y >= 0.0f && p.x < image.width && p.y < image.height)) continue;
    const int c = std::min(cols - 1, static_cast<int>(p.x * cols / image.width));
    const int r = std::min(rows - 1, static_cast<int>(p.y * rows / image.height));
    held[static_cast<size_t>(r) * cols + c] = 1;
  }
  return static_cast<size_t>(std::count(held.begin(), held.end(), 1));
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
    case HypothesisKind::kFar:
      return "far";
  }
  return "unknown";
}

}  // namespace icgm
