#include "core/place/place_recognizer.h"

#include <algorithm>
#include <set>

#include "core/place/geometric_verification.h"

namespace icgm {

PlaceRecognizer::PlaceRecognizer(const PlaceRecognitionOptions& options,
                                 const DictionaryOptions& dictionary,
                                 const std::optional<CameraIntrinsics>& intrinsics)
    : options_(options),
      intrinsics_(intrinsics),
      dictionary_(dictionary),
      temporal_(options.temporal) {}

Status PlaceRecognizer::Process(int id, const FeatureSet& features,
                                const std::vector<uint8_t>& verified, PlaceDecision* decision) {
  const Status s = Recognize(id, features, verified, decision);
  if (!s.ok()) return s;
  return Add();
}

Status PlaceRecognizer::Recognize(int id, const FeatureSet& features,
                                  const std::vector<uint8_t>& verified, PlaceDecision* decision) {
  pending_.reset();
  *decision = PlaceDecision();
  decision->query = id;
  const bool weighted = verified.size() == features.size() && !features.empty();
  // Rows that take part and their weights; unverified rows are left out at weight 0.
  cv::Mat descriptors;
  std::vector<float> weights;
  if (!weighted) {
    descriptors = features.descriptors;
    weights.assign(static_cast<size_t>(descriptors.rows), 1.f);
  } else {
    const float unverified = static_cast<float>(options_.unverified_weight);
    for (int r = 0; r < features.descriptors.rows; ++r) {
      const float w = verified[static_cast<size_t>(r)] ? 1.f : unverified;
      if (w <= 0.f) continue;
      descriptors.push_back(features.descriptors.row(r));
      weights.push_back(w);
    }
  }
  WordAssignment words;
  const Status s = dictionary_.Quantize(descriptors, &words);
  if (!s.ok()) return s;
  std::set<int> distinct;
  int unseen = 0;
  for (int w : words) {
    if (w < 0) {
      ++unseen;
    } else {
      distinct.insert(w);
    }
  }
  decision->words = static_cast<int>(distinct.size()) + unseen;

  std::vector<int> hypotheses;
  std::vector<double> scores;
  for (const DictionaryMatch& m : dictionary_.Score(words, 0, &weights)) {  // best first
    if (m.score < options_.min_score) break;
    if (id - m.keyframe_id <= options_.exclude_recent_images) continue;
    hypotheses.push_back(m.keyframe_id);
    scores.push_back(m.score);
    if (static_cast<int>(hypotheses.size()) >= options_.candidates) break;
  }
  if (!hypotheses.empty()) {
    decision->best_candidate = hypotheses.front();
    decision->best_score = scores.front();
  }
  if (!hypotheses.empty() && decision->words < options_.min_query_words) {
    decision->rejected = "too few words: " + std::to_string(decision->words) + " < " +
                         std::to_string(options_.min_query_words);
    hypotheses.clear();
  }
  for (size_t i = 0; i < hypotheses.size(); ++i) {
    const int candidate = hypotheses[i];
    if (!temporal_.Consistent(id, candidate)) {
      if (i == 0) decision->rejected = "not temporally consistent";
      continue;
    }
    if (options_.geometry.enabled) {
      const auto it = features_.find(candidate);
      if (it == features_.end()) continue;
      const GeometricCheck check =
          VerifyGeometry(features, it->second, options_.geometry, intrinsics_);
      if (!check.status.ok()) {
        if (i == 0) decision->rejected = check.status.reason();
        continue;
      }
      decision->inliers = check.inliers;
    }
    decision->match = candidate;
    decision->score = scores[i];
    decision->rejected.clear();
    break;
  }
  temporal_.Record(id, hypotheses);
  pending_ = Pending{id, features, descriptors, std::move(weights), std::move(words)};
  return Status::Ok();
}

Status PlaceRecognizer::Add() {
  if (!pending_) return Status::Error("place recognizer: Add without a Recognize before it");
  Pending p = std::move(*pending_);
  pending_.reset();
  if (p.descriptors.rows > 0) {
    const Status s = dictionary_.Add(p.id, p.descriptors, nullptr, &p.words, &p.weights);
    if (!s.ok()) return s;
  }
  if (options_.geometry.enabled) features_[p.id] = std::move(p.features);
  return Status::Ok();
}

}  // namespace icgm
