#include "core/odometry/hypothesis_evidence.h"

#include <algorithm>
#include <cmath>
#include <cstddef>
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

double MedianDepthAt(const cv::Mat& depth_m, const std::vector<cv::Point2f>& px) {
  std::vector<float> z;
  for (const cv::Point2f& p : px) {
    const int x = static_cast<int>(std::lround(p.x)), y = static_cast<int>(std::lround(p.y));
    if (depth_m.empty() || x < 0 || y < 0 || x >= depth_m.cols || y >= depth_m.rows) continue;
    const float d = depth_m.at<float>(y, x);
    if (std::isfinite(d) && d > 0.0f) z.push_back(d);
  }
  if (z.empty()) return std::nan("");
  const auto middle = z.begin() + static_cast<std::ptrdiff_t>(z.size() / 2);
  std::nth_element(z.begin(), middle, z.end());
  return *middle;
}

size_t ChooseByDepthOrder(const std::vector<double>& score,
                          const std::vector<double>& median_depth_m,
                          const std::vector<size_t>& inliers, size_t chosen, double margin,
                          double min_gap_m, size_t min_inliers) {
  if (score.empty() || chosen >= score.size()) return chosen;
  const double best = *std::max_element(score.begin(), score.end());
  const double floor = (1.0 - margin) * best;
  const double chosen_depth = median_depth_m[chosen];
  size_t winner = chosen;
  // The farthest; of equally far sets, the later one.
  double farthest = std::isfinite(chosen_depth) ? chosen_depth + min_gap_m : -INFINITY;
  for (size_t i = 0; i < score.size(); ++i) {
    if (i == chosen || score[i] < floor || inliers[i] < min_inliers) continue;
    if (std::isfinite(median_depth_m[i]) && median_depth_m[i] >= farthest) {
      farthest = median_depth_m[i];
      winner = i;
    }
  }
  return winner;
}

size_t ChooseWithinPredictionGate(const std::vector<double>& score,
                                  const std::vector<double>& from_prediction_m,
                                  const std::vector<size_t>& inliers, size_t chosen,
                                  double gate_m, size_t min_inliers) {
  if (chosen >= score.size() || !(gate_m > 0.0)) return chosen;
  const auto inside = [&](size_t i) { return from_prediction_m[i] <= gate_m; };  // NaN: false
  if (inside(chosen)) return chosen;
  size_t winner = chosen;
  for (size_t i = 0; i < score.size(); ++i) {
    if (i == chosen || !inside(i) || inliers[i] < min_inliers) continue;
    if (winner == chosen || score[i] > score[winner]) winner = i;
  }
  return winner;
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

bool ChosenSetNearerThan(const std::vector<JudgedHypothesis>& judged, int chosen, double near_m) {
  if (near_m <= 0.0 || chosen < 0 || static_cast<size_t>(chosen) >= judged.size()) return false;
  const double depth_m = judged[static_cast<size_t>(chosen)].median_depth_m;
  return std::isfinite(depth_m) && depth_m < near_m;
}

}  // namespace icgm
