#include "core/place/place_options.h"

#include "core/common/option_reader.h"

namespace icgm {

void ReadOptions(const OptionReader& reader, TemporalConsistencyOptions* o) {
  reader.Read("consistent_queries", &o->consistent_queries, 0, 100);
  reader.Read("window_images", &o->window_images, 0, 1 << 20);
  reader.Read("continuation", &o->continuation);
  reader.Read("continuation_min_score", &o->continuation_min_score, 0.0, 1.0);
  reader.Read("continuation_min_inliers", &o->continuation_min_inliers, 0, 1 << 20);
  if (o->continuation_min_inliers > 0 && o->continuation_min_inliers < 8) {
    throw LoadError(reader.path() + ".continuation_min_inliers: 0 (off) or at least 8 (the " +
                    "epipolar check's minimum)");
  }
}

void ReadOptions(const OptionReader& reader, GeometricVerificationOptions* o) {
  reader.Read("enabled", &o->enabled);
  reader.ReadEnum("matching", &o->matching);
  reader.Read("ratio", &o->ratio, 0.1, 1.0);
  reader.Read("ransac_threshold_px", &o->ransac_threshold_px, 0.01, 100.0);
  reader.Read("ransac_confidence", &o->ransac_confidence, 0.5, 0.999999);
  reader.Read("min_inliers", &o->min_inliers, 8, 1 << 20);
  reader.Read("descriptor_fallback", &o->descriptor_fallback);
  reader.Read("rgbd", &o->rgbd);
  reader.Read("rgbd_inlier_m", &o->rgbd_inlier_m, 0.001, 10.0);
  reader.Read("rgbd_max_iterations", &o->rgbd_max_iterations, 1, 1000000);
  reader.Read("rgbd_max_translation_m", &o->rgbd_max_translation_m, 0.0, 100.0);
  reader.Read("rgbd_max_rotation_deg", &o->rgbd_max_rotation_deg, 0.0, 180.0);
  reader.Read("rgbd_nearest", &o->rgbd_nearest);
  reader.Read("rgbd_descriptor_fallback", &o->rgbd_descriptor_fallback);
  reader.Read("rgbd_agreement_min_inliers", &o->rgbd_agreement_min_inliers, 0, 1 << 20);
  if (o->rgbd_agreement_min_inliers > 0 && o->rgbd_agreement_min_inliers < 3) {
    throw LoadError(reader.path() + ".rgbd_agreement_min_inliers: 0 (off) or at least 3 (a " +
                    "rigid motion's minimum)");
  }
  if (o->rgbd && o->matching != PlaceMatching::kWords) {
    throw LoadError(reader.path() + ".rgbd: needs matching: words (the 3-D points of the " +
                    "word correspondences)");
  }
}

void ReadOptions(const OptionReader& reader, PlaceRecognitionOptions* o) {
  reader.Read("min_score", &o->min_score, 0.0, 1.0);
  reader.Read("exclude_recent_images", &o->exclude_recent_images, 0, 1 << 30);
  reader.Read("unverified_weight", &o->unverified_weight, 0.0, 1.0);
  reader.Read("weight_by_verified_share", &o->weight_by_verified_share);
  reader.Read("min_query_words", &o->min_query_words, 0, 1 << 20);
  reader.Read("candidates", &o->candidates, 1, 100);
  reader.Read("depth_candidates", &o->depth_candidates, 0, 100);
  reader.Read("depth_min_score", &o->depth_min_score, 0.0, 1.0);
}

void ReadPlaceRecognitionFile(const OptionReader& root, PlaceRecognitionOptions* o) {
  const OptionReader place = root.Section("place_recognition");
  const OptionReader temporal = root.Section("temporal_consistency");
  const OptionReader geometry = root.Section("geometric_verification");
  ReadOptions(place, o);
  ReadOptions(temporal, &o->temporal);
  ReadOptions(geometry, &o->geometry);
  OptionReader::RejectUnknownKeys({&place, &temporal, &geometry, &root});
}

}  // namespace icgm
