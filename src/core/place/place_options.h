// Options of appearance-only place recognition (place_recognizer.h), read from
// config/place_recognition.yaml: feature weighting, the minimum-words guard, the temporal
// consistency of loop hypotheses and their geometric verification. Each stage can be switched
// off, which gives the plain dictionary of thesis 4.2 (PIRF-nav 2.0 style).
#pragma once

#include <string>

#include "core/common/enum_names.h"

namespace icgm {

class OptionReader;

// A loop hypothesis (query q -> earlier image c) is consistent when each of the
// `consistent_queries` queries before q (q-1, q-2, ...) had a hypothesis within `window_images`
// of c: consecutive queries agree on neighbouring places (PIRF-nav 2.0; iBoW-LCD's temporal
// islands). 0 queries: off.
//
// Continuation (ours; recovers rather than drops): when the previous query reported a loop to
// image m, the earlier images within `window_images` of m that score at least
// `continuation_min_score` (below place_recognition.min_score) are hypotheses too, after the
// regular ones, and pass the same checks: a revisit goes on from where the last one was, and
// its next image may share too few words with the earlier view to score min_score (blur,
// walkers in front, a turned view) while its geometry still fits. When the last two loops
// moved by one or more images in one direction, the image next in that direction is tried
// first (then by distance to it), else by score.
//
// (ours) `continuation_min_inliers` > 0: a continuation hypothesis is verified by the epipolar
// check with this many inliers (instead of geometric_verification.min_inliers): the temporal
// agreement (the previous query's loop is next to it) is the second piece of evidence a weak
// view lacks (walkers covering most of the view). 0: min_inliers, as every hypothesis; the
// thesis profile: 0.
struct TemporalConsistencyOptions {
  int consistent_queries = 0;
  int window_images = 2;
  bool continuation = true;
  double continuation_min_score = 0.02;
  int continuation_min_inliers = 12;
};

// Epipolar check of a loop hypothesis on the images' features: correspondences, then RANSAC on
// the essential matrix (camera intrinsics known) or the fundamental matrix (not known); the
// loop is reported when at least `min_inliers` correspondences fit. Correspondences
// (`matching`): "words", features of the two images quantized to the same dictionary word,
// each word once in each image (free: the query has its words already); "descriptors": mutual
// ratio-test descriptor matching (more matches, a few ms per candidate).
enum class PlaceMatching { kWords, kDescriptors };

template <>
struct EnumNames<PlaceMatching> {
  static constexpr EnumName<PlaceMatching> kNames[] = {
      {PlaceMatching::kWords, "words"}, {PlaceMatching::kDescriptors, "descriptors"}};
};

struct GeometricVerificationOptions {
  bool enabled = true;
  PlaceMatching matching = PlaceMatching::kWords;
  double ratio = 0.8;
  double ransac_threshold_px = 2.0;
  double ransac_confidence = 0.999;
  int min_inliers = 20;
  // matching: words: a hypothesis whose word correspondences fail the check is checked again on
  // ratio-test descriptor matches (more correspondences where few features fell into the same
  // word: blur, another viewpoint); stores every image's features (about 35 KB per image of
  // 1,000 ORB features).
  bool descriptor_fallback = true;
  // RGB-D check (needs matching: words): when both images come with depth, the word
  // correspondences whose keypoints have a 3-D point on both sides must fit one rigid motion
  // (RANSAC + Horn, core/registration/ransac_horn.h): at least min_inliers within
  // rgbd_inlier_m. It replaces the epipolar check for such pairs; without depth the epipolar
  // check applies. A scene with the same look but another 3-D layout (a replica at another
  // scale, a poster of the place) has a valid epipolar geometry but no rigid one.
  bool rgbd = false;
  double rgbd_inlier_m = 0.05;
  int rgbd_max_iterations = 500;
  // (ours) Bounds of the rigid motion of a hypothesis scoring under
  // place_recognition.min_score (continuation, depth candidates) that the RGB-D check verified:
  // a weak score is trusted only for a camera back near the earlier pose (the bounds of the
  // map's loop links, map.yaml max_link_translation_m and max_link_rad). 0: no bound.
  double rgbd_max_translation_m = 0.45;
  double rgbd_max_rotation_deg = 28.6;
  // (ours) With depth, every hypothesis is checked and, of the verified ones, the one whose
  // motion is smallest (max of translation / rgbd_max_translation_m and rotation /
  // rgbd_max_rotation_deg) is the loop: the nearest earlier view rather than the best-scored
  // one, which on a sparse sequence is often a view of the same scene from farther away. A
  // hypothesis the epipolar check verified gets its motion from the RGB-D fit (word
  // correspondences, then descriptor matches with depth), which only ranks it; one with no
  // fit is the loop only when no verified hypothesis before it has a motion. Without depth
  // the first verified hypothesis is the loop, as with false.
  bool rgbd_nearest = false;
  // (ours) An RGB-D check failing on word correspondences is retried on ratio-test descriptor
  // matches with depth on both sides (as descriptor_fallback does for the epipolar check);
  // stores every image's features and their 3-D points.
  bool rgbd_descriptor_fallback = true;
  // (ours) An RGB-D check that fails with at least `rgbd_agreement_min_inliers` 3-D inliers
  // (fewer than min_inliers) is accepted when the epipolar check of the same pair verifies it
  // (words, then descriptor matches, min_inliers): two independent geometries agree (walkers
  // hide most of the depth-lifted matches). The motion bound still applies. 0: off (thesis
  // profile).
  int rgbd_agreement_min_inliers = 12;
};

struct PlaceRecognitionOptions {
  // Dictionary score below which an earlier image is no loop candidate, in [0, 1].
  double min_score = 0.05;
  // The most recent images (ids this close to the query) are never loop candidates.
  int exclude_recent_images = 20;
  // Weight of a feature that ICGM did not verify (verified features weigh 1): 0 scores the
  // verified ones alone (thesis 4.2), 1 treats all alike (plain features).
  double unverified_weight = 0.5;
  // Weigh unverified features by the evidence ICGM had in their image: an image whose features
  // ICGM verified a share v of gives its unverified ones max(unverified_weight, 1 - v). Where
  // consecutive images overlap little (sparse sequences: v of a few %), ICGM could check
  // almost nothing, so not being verified says little and those features weigh almost as
  // verified ones (as plain features do); where ICGM verified most of the image (dense
  // sequences, v ~ 0.5+), what it rejected is likely to move (walkers) and weighs
  // unverified_weight. false: every unverified feature weighs unverified_weight.
  bool weight_by_verified_share = true;
  // Queries with fewer distinct words (unseen descriptors count one each) claim no loop.
  int min_query_words = 50;
  // Best-scored candidates (not among the most recent images) tried per query, best first.
  int candidates = 3;
  // (ours) Depth candidates: when the query has depth (geometric_verification.rgbd), the
  // earlier images with depth among its `depth_candidates` best-scored ones that score at least
  // `depth_min_score` (under min_score) are hypotheses too, after the others; the RGB-D check
  // and its motion bound (rgbd_max_translation_m, rgbd_max_rotation_deg) decide. The first
  // image of a revisit often scores under min_score when little of the view was seen from that
  // spot (sparse images, walkers in front); one rigid motion of 20+ 3-D points within the bound
  // is evidence the score cannot give. 0: off.
  int depth_candidates = 5;
  double depth_min_score = 0.02;
  TemporalConsistencyOptions temporal;
  GeometricVerificationOptions geometry;
};

// Sections `place_recognition:`, `temporal_consistency:`, `geometric_verification:`; throws
// LoadError naming a bad value.
void ReadOptions(const OptionReader& reader, TemporalConsistencyOptions* options);
void ReadOptions(const OptionReader& reader, GeometricVerificationOptions* options);
void ReadOptions(const OptionReader& reader, PlaceRecognitionOptions* options);
// The whole file: the three sections above; unknown keys (in a section or at the top level) are
// a LoadError naming them.
void ReadPlaceRecognitionFile(const OptionReader& root, PlaceRecognitionOptions* options);

}  // namespace icgm
