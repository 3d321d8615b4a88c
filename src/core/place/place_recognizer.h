// Appearance-only place recognition over an image sequence (thesis 4.2: ICGM-based online
// incremental appearance-only SLAM, PIRF-nav 2.0 style: the robust features ICGM extracts enter
// an incremental dictionary, and an image's best-scored earlier image is its loop). Steps 1, 2
// and 4 and the temporal check of 3 are ours, not in the thesis; they keep it precise when the
// ICGM-verified features are few (sparse sequences, crowds):
//  1. (ours) feature weighting: every feature goes into the incremental dictionary, an
//     ICGM-verified one with weight 1 and an unverified one with `unverified_weight`
//     (visual_dictionary.h; the thesis keeps the verified ones only: unverified_weight 0,
//     weight_by_verified_share false); verified words therefore dominate where ICGM found many
//     (crowds: walkers' features are the unverified ones), and unverified ones still recognize a
//     place where consecutive images share little (sparse sequences, where ICGM discards most
//     features); with `weight_by_verified_share` an image's unverified features weigh
//     max(unverified_weight, 1 - its verified share): the less ICGM could check, the less not
//     being verified counts against a feature;
//  2. (ours) minimum-words guard: a query with fewer than `min_query_words` distinct words
//     claims no loop (a blurred or blank image matches anything a little);
//  3. the `candidates` best-scored earlier images (score >= min_score, not among the
//     `exclude_recent_images` latest) are hypotheses (the thesis: the best one); (ours) after a
//     loop, images next to it scoring at least `continuation_min_score` are hypotheses too
//     (temporal continuation, place_options.h); (ours) a query with depth also tries its
//     `depth_candidates` best-scored images with depth down to `depth_min_score`, after the
//     others, by the RGB-D check within a motion bound (depth candidates); (ours) each must be
//     temporally consistent (temporal_consistency.h; off by default) and
//  4. (ours) geometrically verified (geometric_verification.h): epipolar RANSAC, or, with
//     `geometric_verification.rgbd` and depth for both images, RANSAC + Horn on the 3-D points
//     of the word correspondences (for the depth candidates always); the first that passes is
//     the loop, or with `rgbd_nearest` (queries with depth) the verified one whose camera
//     moved least by the RGB-D fit (fitted for ranking also where the image check verified);
//     (ours) two pieces of evidence agreeing pass on fewer inliers: a continuation hypothesis
//     (next to the previous loop) on `continuation_min_inliers` epipolar inliers, an RGB-D check
//     on `rgbd_agreement_min_inliers` 3-D inliers when the pair's epipolar check passes.
// Each image is added to the dictionary after its query.
#pragma once

#include <limits>
#include <optional>
#include <string>
#include <unordered_map>
#include <vector>

#include <Eigen/Core>

#include "core/common/camera.h"
#include "core/common/status.h"
#include "core/features/feature_extractor.h"
#include "core/map/visual_dictionary.h"
#include "core/place/place_options.h"
#include "core/place/temporal_consistency.h"

namespace icgm {

// One loop hypothesis a query checked and what became of it.
struct PlaceHypothesis {
  int candidate = -1;
  double score = 0.0;
  int correspondences = 0;  // geometric verification: putative correspondences
  int inliers = 0;          // ... and those fitting one geometry
  std::string verdict;      // empty: accepted; else why not
  // The rigid motion fitted between the two cameras (RGB-D check or motion measurement); NaN:
  // none fitted.
  double translation_m = std::numeric_limits<double>::quiet_NaN();
  double rotation_deg = std::numeric_limits<double>::quiet_NaN();
};

struct PlaceDecision {
  int query = -1;
  int match = -1;      // the recognized earlier image, -1: a new place
  double score = 0.0;  // its dictionary score (0 for a new place)
  // Best-scored hypothesis before the checks (-1: none above min_score), and why it was not
  // accepted (empty when it was, or when there was none).
  int best_candidate = -1;
  double best_score = 0.0;
  std::string rejected;
  int words = 0;                         // distinct words of the query
  int inliers = 0;                       // geometric verification inliers of the match
  std::vector<PlaceHypothesis> checked;  // the hypotheses tried, best-scored first
  // With PlaceRecognizer::set_keep_scores(true): every earlier image's score, best first
  // (including the excluded recent ones), for diagnostics.
  std::vector<DictionaryMatch> scores;
};

class PlaceRecognizer {
 public:
  // `intrinsics`: the camera, for the essential-matrix check; nullopt: fundamental matrix.
  PlaceRecognizer(const PlaceRecognitionOptions& options, const DictionaryOptions& dictionary,
                  const std::optional<CameraIntrinsics>& intrinsics = std::nullopt);

  // Queries with image `id`'s features (ids increase strictly), then adds them. `verified`: per
  // keypoint, 1 when ICGM kept it; empty: all count as verified (plain features). Fails on
  // descriptors the dictionary cannot take, changing nothing. `points_m` (optional, one per
  // keypoint): its 3-D point in the camera frame from depth, NaN where there is none; used by
  // the RGB-D check.
  Status Process(int id, const FeatureSet& features, const std::vector<uint8_t>& verified,
                 PlaceDecision* decision, const std::vector<Eigen::Vector3d>* points_m = nullptr);
  // Process in two steps (to time them apart): Recognize queries and checks, changing only the
  // temporal history; Add then inserts the image just recognized.
  Status Recognize(int id, const FeatureSet& features, const std::vector<uint8_t>& verified,
                   PlaceDecision* decision, const std::vector<Eigen::Vector3d>* points_m = nullptr);
  Status Add();

  const VisualDictionary& dictionary() const { return dictionary_; }
  // Diagnostics: decisions carry every earlier image's score (PlaceDecision::scores).
  void set_keep_scores(bool keep) { keep_scores_ = keep; }
  const PlaceRecognitionOptions& options() const { return options_; }

 private:
  PlaceRecognitionOptions options_;
  std::optional<CameraIntrinsics> intrinsics_;
  VisualDictionary dictionary_;
  TemporalConsistency temporal_;
  bool keep_scores_ = false;
  // Continuation: the loop the previous query reported (-1: none) and the direction in which
  // the last two consecutive loops moved through the earlier images (-1, 0: unknown, +1).
  int previous_match_ = -1;
  int previous_step_ = 0;
  // What geometric verification needs of an earlier image.
  struct Stored {
    FeatureSet features;                    // matching: descriptors
    std::vector<cv::Point2f> points;        // matching: words; the rows in the dictionary ...
    WordAssignment words;                   // ... and their words
    std::vector<Eigen::Vector3d> points_m;  // rgbd: 3-D point per row (NaN: none); empty: no depth
    std::vector<Eigen::Vector3d> feature_points_m;  // rgbd_descriptor_fallback: per keypoint
  };
  // Row pairs (query, candidate) of rows quantized to the same word, each word once in each.
  static std::vector<std::pair<int, int>> WordCorrespondences(const WordAssignment& query_words,
                                                              const WordAssignment& candidate);

  // rgbd_nearest: the camera motion to a stored image that a hypothesis verified on the images
  // alone has, by the RGB-D fit (word correspondences, then descriptor matches with depth);
  // NaN when it does not fit. `row_points_m`: per dictionary row of the query,
  // `feature_points_m`: per keypoint.
  double RigidMotion(const WordAssignment& words, const FeatureSet& features,
                     const std::vector<Eigen::Vector3d>& feature_points_m,
                     const std::vector<Eigen::Vector3d>& row_points_m, const Stored& stored,
                     double* rotation_deg) const;

  std::unordered_map<int, Stored> stored_;  // by id, for geometric verification
  // The image Recognize saw last, for Add.
  struct Pending {
    int id = -1;
    FeatureSet features;
    cv::Mat descriptors;  // the rows taking part
    std::vector<cv::Point2f> points;
    std::vector<Eigen::Vector3d> points_m;
    std::vector<Eigen::Vector3d> feature_points_m;  // per keypoint of `features`
    std::vector<float> weights;
    WordAssignment words;
  };
  std::optional<Pending> pending_;
};

}  // namespace icgm
