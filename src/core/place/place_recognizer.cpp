#include "core/place/place_recognizer.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <limits>
#include <set>

#include "core/common/fixed_text.h"
#include "core/place/geometric_verification.h"

namespace icgm {

PlaceRecognizer::PlaceRecognizer(const PlaceRecognitionOptions& options,
                                 const DictionaryOptions& dictionary,
                                 const std::optional<CameraIntrinsics>& intrinsics)
    : options_(options),
      intrinsics_(intrinsics),
      dictionary_(dictionary),
      temporal_(options.temporal) {}

namespace {

bool Finite(const Eigen::Vector3d& p) { return p.allFinite(); }

// The word correspondences (query row, stored row) with a finite 3-D point on both sides, as
// the RGB-D check's point pairs.
void RigidWordMatches(const std::vector<std::pair<int, int>>& pairs,
                      const std::vector<Eigen::Vector3d>& query_m,
                      const std::vector<Eigen::Vector3d>& stored_m, std::vector<Eigen::Vector3d>* a,
                      std::vector<Eigen::Vector3d>* b) {
  for (const auto& [q, c] : pairs) {
    if (Finite(query_m[q]) && Finite(stored_m[c])) {
      a->push_back(query_m[q]);
      b->push_back(stored_m[c]);
    }
  }
}

}  // namespace

Status PlaceRecognizer::Process(int id, const FeatureSet& features,
                                const std::vector<uint8_t>& verified, PlaceDecision* decision,
                                const std::vector<Eigen::Vector3d>* points_m) {
  const Status s = Recognize(id, features, verified, decision, points_m);
  if (!s.ok()) return s;
  return Add();
}

Status PlaceRecognizer::Recognize(int id, const FeatureSet& features,
                                  const std::vector<uint8_t>& verified, PlaceDecision* decision,
                                  const std::vector<Eigen::Vector3d>* points_m) {
  pending_.reset();
  // Depth is used by the RGB-D check of every hypothesis (rgbd) or of the depth candidates.
  const bool depth = options_.geometry.enabled &&
                     (options_.geometry.rgbd || options_.depth_candidates > 0) && points_m &&
                     points_m->size() == features.size();
  *decision = PlaceDecision();
  decision->query = id;
  const bool weighted = verified.size() == features.size() && !features.empty();
  // Rows that take part and their weights; unverified rows are left out at weight 0.
  cv::Mat descriptors;
  std::vector<float> weights;
  std::vector<cv::Point2f> points;
  std::vector<Eigen::Vector3d> points3;
  if (!weighted) {
    descriptors = features.descriptors;
    weights.assign(static_cast<size_t>(descriptors.rows), 1.f);
    for (const cv::KeyPoint& k : features.keypoints) points.push_back(k.pt);
    if (depth) points3 = *points_m;
  } else {
    float unverified = static_cast<float>(options_.unverified_weight);
    if (options_.weight_by_verified_share) {
      const auto kept =
          std::count_if(verified.begin(), verified.end(), [](uint8_t v) { return v; });
      const double share = static_cast<double>(kept) / static_cast<double>(verified.size());
      unverified = static_cast<float>(std::max(options_.unverified_weight, 1.0 - share));
    }
    for (int r = 0; r < features.descriptors.rows; ++r) {
      const float w = verified[static_cast<size_t>(r)] ? 1.f : unverified;
      if (w <= 0.f) continue;
      descriptors.push_back(features.descriptors.row(r));
      weights.push_back(w);
      points.push_back(features.keypoints[static_cast<size_t>(r)].pt);
      if (depth) points3.push_back((*points_m)[static_cast<size_t>(r)]);
    }
  }
  points.resize(static_cast<size_t>(descriptors.rows));
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
  const std::vector<DictionaryMatch> scored = dictionary_.Score(words, 0, &weights);
  if (keep_scores_) decision->scores = scored;
  for (const DictionaryMatch& m : scored) {  // best first
    if (m.score < options_.min_score) break;
    if (id - m.keyframe_id <= options_.exclude_recent_images) continue;
    hypotheses.push_back(m.keyframe_id);
    scores.push_back(m.score);
    if (static_cast<int>(hypotheses.size()) >= options_.candidates) break;
  }
  const TemporalConsistencyOptions& temporal = options_.temporal;
  // Hypotheses from here on (up to the depth candidates) are continuations.
  const size_t first_continuation = hypotheses.size();
  if (temporal.continuation && previous_match_ >= 0) {
    // Images near the previous query's loop scoring between continuation_min_score and
    // min_score, best first (the regular hypotheses scored min_score at least).
    std::vector<DictionaryMatch> near;
    for (const DictionaryMatch& m : scored) {
      if (m.score >= options_.min_score) continue;
      if (m.score < temporal.continuation_min_score) break;
      if (id - m.keyframe_id <= options_.exclude_recent_images) continue;
      if (std::abs(m.keyframe_id - previous_match_) > temporal.window_images) continue;
      near.push_back(m);
    }
    if (previous_step_ != 0) {  // the run goes on: nearest to its next image first
      const int next = previous_match_ + previous_step_;
      std::stable_sort(near.begin(), near.end(),
                       [next](const DictionaryMatch& a, const DictionaryMatch& b) {
                         return std::abs(a.keyframe_id - next) < std::abs(b.keyframe_id - next);
                       });
    }
    for (size_t k = 0; k < near.size() && static_cast<int>(k) < options_.candidates; ++k) {
      hypotheses.push_back(near[k].keyframe_id);
      scores.push_back(near[k].score);
    }
  }
  // Hypotheses from here on are depth candidates (always the RGB-D check).
  const size_t first_depth_candidate = hypotheses.size();
  if (depth && options_.depth_candidates > 0) {
    // Depth candidates: earlier images with depth among the query's best-scored ones, down to
    // depth_min_score; the RGB-D check and its motion bound decide.
    int rank = 0;
    for (const DictionaryMatch& m : scored) {
      if (m.score < options_.depth_min_score) break;
      if (id - m.keyframe_id <= options_.exclude_recent_images) continue;
      if (++rank > options_.depth_candidates) break;
      if (std::find(hypotheses.begin(), hypotheses.end(), m.keyframe_id) != hypotheses.end()) {
        continue;
      }
      const auto it = stored_.find(m.keyframe_id);
      if (it == stored_.end() || it->second.points_m.empty()) continue;
      hypotheses.push_back(m.keyframe_id);
      scores.push_back(m.score);
    }
  }
  if (!hypotheses.empty()) {
    decision->best_candidate = hypotheses.front();
    decision->best_score = scores.front();
  }
  for (size_t i = 0; i < hypotheses.size(); ++i) {
    decision->checked.push_back({hypotheses[i], scores[i], 0, 0, "not checked"});
  }
  if (!hypotheses.empty() && decision->words < options_.min_query_words) {
    decision->rejected = "too few words: " + std::to_string(decision->words) + " < " +
                         std::to_string(options_.min_query_words);
    for (PlaceHypothesis& h : decision->checked) h.verdict = decision->rejected;
    hypotheses.clear();
  }
  const GeometricVerificationOptions& geometry = options_.geometry;
  // rgbd_nearest: the rigidly verified hypothesis with the smallest motion (index, size).
  int nearest = -1;
  double nearest_motion = 0.0;
  for (size_t i = 0; i < hypotheses.size(); ++i) {
    const int candidate = hypotheses[i];
    PlaceHypothesis& hypothesis = decision->checked[i];
    if (!temporal_.Consistent(id, candidate)) {
      hypothesis.verdict = "not temporally consistent";
      if (i == 0) decision->rejected = hypothesis.verdict;
      continue;
    }
    if (options_.geometry.enabled) {
      const auto it = stored_.find(candidate);
      if (it == stored_.end()) {
        hypothesis.verdict = "no stored image";
        continue;
      }
      GeometricCheck check;
      if (options_.geometry.matching == PlaceMatching::kDescriptors) {
        check = VerifyGeometry(features, it->second.features, options_.geometry, intrinsics_);
      } else {
        const Stored& stored = it->second;
        const auto pairs = WordCorrespondences(words, stored.words);
        const bool rigid = depth && !stored.points_m.empty() &&
                           (options_.geometry.rgbd || i >= first_depth_candidate);
        const bool continuation = i >= first_continuation && i < first_depth_candidate;
        // The fallbacks retry a failed check of the same kind on more correspondences: an
        // epipolar check on descriptor matches, an RGB-D check on descriptor matches with
        // depth (rgbd_descriptor_fallback); they never turn an RGB-D rejection into an
        // image-only acceptance.
        const auto epipolar = [&](const GeometricVerificationOptions& o) {
          std::vector<cv::Point2f> a, b;
          for (const auto& [q, c] : pairs) {
            a.push_back(points[q]);
            b.push_back(stored.points[c]);
          }
          GeometricCheck out = VerifyEpipolar(a, b, o, intrinsics_);
          if (!out.status.ok() && o.descriptor_fallback) {
            const GeometricCheck retry = VerifyGeometry(features, stored.features, o, intrinsics_);
            if (retry.status.ok() || retry.inliers > out.inliers) out = retry;
          }
          return out;
        };
        std::vector<Eigen::Vector3d> rigid_a, rigid_b;  // the RGB-D check's word matches
        if (rigid) RigidWordMatches(pairs, points3, stored.points_m, &rigid_a, &rigid_b);
        const auto rigid_fit = [&](const GeometricVerificationOptions& o) {
          GeometricCheck out = VerifyRigid(rigid_a, rigid_b, o);
          if (!out.status.ok() && o.rgbd_descriptor_fallback && !stored.feature_points_m.empty()) {
            const GeometricCheck retry = VerifyRigidGeometry(features, *points_m, stored.features,
                                                             stored.feature_points_m, o);
            if (retry.status.ok() || retry.inliers > out.inliers) out = retry;
          }
          return out;
        };
        check = rigid ? rigid_fit(geometry) : epipolar(geometry);
        if (!check.status.ok() && !rigid && continuation && temporal.continuation_min_inliers > 0 &&
            temporal.continuation_min_inliers < geometry.min_inliers) {
          // Temporal agreement: a continuation hypothesis needs fewer epipolar inliers.
          GeometricVerificationOptions fewer = geometry;
          fewer.min_inliers = temporal.continuation_min_inliers;
          const GeometricCheck retry = epipolar(fewer);
          if (retry.status.ok()) check = retry;
        }
        if (!check.status.ok() && rigid && geometry.rgbd_agreement_min_inliers > 0 &&
            geometry.rgbd_agreement_min_inliers < geometry.min_inliers) {
          // Two geometries agree: the rigid fit on fewer 3-D inliers (word matches, then
          // descriptor matches with depth) and the epipolar check at min_inliers.
          GeometricVerificationOptions fewer = geometry;
          fewer.min_inliers = geometry.rgbd_agreement_min_inliers;
          const GeometricCheck fit = rigid_fit(fewer);
          if (fit.status.ok() && epipolar(geometry).status.ok()) check = fit;
        }
      }
      hypothesis.correspondences = check.matches;
      hypothesis.inliers = check.inliers;
      const bool rigid_checked = std::isfinite(check.translation_m);
      if (check.status.ok() && !rigid_checked && geometry.rgbd_nearest && depth) {
        // Verified on the images alone: its motion is measured by the RGB-D fit, which here
        // only ranks (a failed fit leaves the hypothesis verified, without a motion).
        check.translation_m =
            RigidMotion(words, features, *points_m, points3, it->second, &check.rotation_deg);
      }
      hypothesis.translation_m = check.translation_m;
      hypothesis.rotation_deg = check.rotation_deg;
      if (check.status.ok() && rigid_checked) {
        // Rigidly verified: a weak score (or a depth candidate) needs the camera near the
        // earlier pose.
        const bool bounded = scores[i] < options_.min_score || i >= first_depth_candidate;
        if (bounded && geometry.rgbd_max_translation_m > 0.0 &&
            check.translation_m > geometry.rgbd_max_translation_m) {
          check.status = Status::Error("rgbd motion " + FormatFixed(check.translation_m, 2) +
                                       " m > " + FormatFixed(geometry.rgbd_max_translation_m, 2) +
                                       " m (weak hypothesis)");
        } else if (bounded && geometry.rgbd_max_rotation_deg > 0.0 &&
                   check.rotation_deg > geometry.rgbd_max_rotation_deg) {
          check.status = Status::Error("rgbd motion " + FormatFixed(check.rotation_deg, 1) +
                                       " deg > " + FormatFixed(geometry.rgbd_max_rotation_deg, 1) +
                                       " deg (weak hypothesis)");
        }
      }
      if (!check.status.ok()) {
        hypothesis.verdict = check.status.reason();
        if (i == 0) decision->rejected = check.status.reason();
        continue;
      }
      if (geometry.rgbd_nearest && std::isfinite(check.translation_m)) {
        const double motion = std::max(geometry.rgbd_max_translation_m > 0.0
                                           ? check.translation_m / geometry.rgbd_max_translation_m
                                           : check.translation_m,
                                       geometry.rgbd_max_rotation_deg > 0.0
                                           ? check.rotation_deg / geometry.rgbd_max_rotation_deg
                                           : 0.0);
        hypothesis.verdict = "verified, motion " + FormatFixed(check.translation_m, 3) + " m " +
                             FormatFixed(check.rotation_deg, 1) + " deg";
        if (nearest < 0 || motion < nearest_motion) {
          nearest = static_cast<int>(i);
          nearest_motion = motion;
        }
        continue;  // the others are checked too
      }
    }
    if (nearest >= 0) {  // a rigid loop was found: only a nearer rigid one replaces it
      hypothesis.verdict = "verified (image only), a rigidly verified hypothesis is taken";
      continue;
    }
    hypothesis.verdict.clear();
    decision->inliers = hypothesis.inliers;
    decision->match = candidate;
    decision->score = scores[i];
    decision->rejected.clear();
    break;
  }
  if (nearest >= 0) {
    PlaceHypothesis& hypothesis = decision->checked[static_cast<size_t>(nearest)];
    for (PlaceHypothesis& h : decision->checked) {
      if (h.verdict.rfind("verified, motion", 0) == 0 && &h != &hypothesis) {
        h.verdict = "verified, image " + std::to_string(hypothesis.candidate) +
                    " is nearer: " + h.verdict.substr(std::string("verified, ").size());
      }
    }
    hypothesis.verdict.clear();
    decision->inliers = hypothesis.inliers;
    decision->match = hypothesis.candidate;
    decision->score = hypothesis.score;
    decision->rejected.clear();
  }
  temporal_.Record(id, hypotheses);
  previous_step_ =
      decision->match >= 0 && previous_match_ >= 0 && decision->match != previous_match_
          ? (decision->match > previous_match_ ? 1 : -1)
          : 0;
  previous_match_ = decision->match;
  pending_ = Pending{id,
                     features,
                     descriptors,
                     std::move(points),
                     std::move(points3),
                     depth ? *points_m : std::vector<Eigen::Vector3d>(),
                     std::move(weights),
                     std::move(words)};
  return Status::Ok();
}

Status PlaceRecognizer::Add() {
  if (!pending_) return Status::Error("place recognizer: Add without a Recognize before it");
  Pending p = std::move(*pending_);
  pending_.reset();
  WordAssignment words;
  if (p.descriptors.rows > 0) {
    const Status s = dictionary_.Add(p.id, p.descriptors, &words, &p.words, &p.weights);
    if (!s.ok()) return s;
  }
  if (options_.geometry.enabled) {
    Stored& stored = stored_[p.id];
    const bool rigid_fallback =
        options_.geometry.rgbd_descriptor_fallback && !p.feature_points_m.empty();
    if (options_.geometry.matching == PlaceMatching::kDescriptors ||
        options_.geometry.descriptor_fallback || rigid_fallback) {
      stored.features = std::move(p.features);
    }
    if (rigid_fallback) stored.feature_points_m = std::move(p.feature_points_m);
    if (options_.geometry.matching == PlaceMatching::kWords) {
      stored.points = std::move(p.points);
      stored.points_m = std::move(p.points_m);
      stored.words = std::move(words);
    }
  }
  return Status::Ok();
}

double PlaceRecognizer::RigidMotion(const WordAssignment& words, const FeatureSet& features,
                                    const std::vector<Eigen::Vector3d>& feature_points_m,
                                    const std::vector<Eigen::Vector3d>& row_points_m,
                                    const Stored& stored, double* rotation_deg) const {
  GeometricCheck fit;
  if (!stored.points_m.empty()) {
    std::vector<Eigen::Vector3d> a, b;
    RigidWordMatches(WordCorrespondences(words, stored.words), row_points_m, stored.points_m, &a,
                     &b);
    fit = VerifyRigid(a, b, options_.geometry);
  }
  if (!fit.status.ok() && !stored.feature_points_m.empty()) {
    fit = VerifyRigidGeometry(features, feature_points_m, stored.features, stored.feature_points_m,
                              options_.geometry);
  }
  if (!fit.status.ok()) return std::numeric_limits<double>::quiet_NaN();
  *rotation_deg = fit.rotation_deg;
  return fit.translation_m;
}

std::vector<std::pair<int, int>> PlaceRecognizer::WordCorrespondences(
    const WordAssignment& query_words, const WordAssignment& candidate_words) {
  // (word, row) of each side, sorted by word; words seen twice in an image are ambiguous.
  auto sorted = [](const WordAssignment& words) {
    std::vector<std::pair<int, int>> v;
    v.reserve(words.size());
    for (size_t r = 0; r < words.size(); ++r) {
      if (words[r] >= 0) v.emplace_back(words[r], static_cast<int>(r));
    }
    std::sort(v.begin(), v.end());
    return v;
  };
  const auto q = sorted(query_words);
  const auto c = sorted(candidate_words);
  auto unique_at = [](const std::vector<std::pair<int, int>>& v, size_t i) {
    return (i == 0 || v[i - 1].first != v[i].first) &&
           (i + 1 == v.size() || v[i + 1].first != v[i].first);
  };
  std::vector<std::pair<int, int>> pairs;
  size_t i = 0, j = 0;
  while (i < q.size() && j < c.size()) {
    if (q[i].first < c[j].first) {
      ++i;
    } else if (c[j].first < q[i].first) {
      ++j;
    } else {
      if (unique_at(q, i) && unique_at(c, j)) pairs.emplace_back(q[i].second, c[j].second);
      ++i;
      ++j;
    }
  }
  return pairs;
}

}  // namespace icgm
