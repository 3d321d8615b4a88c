// Putative descriptor matches between two FeatureSets: nearest neighbour with Lowe's ratio test
// (Lowe 2004, sec. 7.1) and an optional mutual (cross) check. Float descriptors use a FLANN
// randomized kd-tree with best-bin-first search (Muja & Lowe 2009), as in the thesis ch. 3;
// binary descriptors use exhaustive Hamming search with hardware popcount (hamming_knn.h) or
// FLANN LSH (`binary_index`).
#pragma once

#include <string>
#include <vector>

#include <Eigen/Core>
#include <opencv2/core.hpp>

#include "core/features/feature_extractor.h"

namespace icgm {

class OptionReader;

// Index for binary descriptors (`matcher.binary_index`): exhaustive Hamming search (exact) or
// FLANN LSH (approximate).
enum class BinaryIndex { kBruteForce, kLsh };

template <>
struct EnumNames<BinaryIndex> {
  static constexpr EnumName<BinaryIndex> kNames[] = {{BinaryIndex::kBruteForce, "bf"},
                                                     {BinaryIndex::kLsh, "lsh"}};
};

struct MatcherOptions {
  // Keep a match when best_distance < ratio * second_best_distance; 1.0 disables the test.
  double ratio = 0.8;
  // Keep a match only when it is also the best match in the b -> a direction.
  bool mutual_check = false;
  // Binary descriptors: "bf" (exhaustive Hamming, exact) or "lsh" (FLANN LSH, approximate).
  // Measured with icgm_benchmark on TUM fr1/xyz, 1000 ORB per frame: see config/icgm.yaml.
  BinaryIndex binary_index = BinaryIndex::kBruteForce;
  // Float descriptors: FLANN kd-tree count and number of leaves checked per query.
  int flann_trees = 4;
  int flann_checks = 64;
  // LSH parameters (binary_index lsh).
  int lsh_tables = 6;
  int lsh_key_bits = 12;
  int lsh_probe_level = 1;
  // Matches with a larger descriptor distance are dropped; <= 0 disables.
  double max_distance = 0.0;
};

// Fills `options` from a `matcher:` section; throws LoadError on bad values.
void ReadOptions(const OptionReader& reader, MatcherOptions* options);

class DescriptorMatcher {
 public:
  explicit DescriptorMatcher(const MatcherOptions& options);

  // Matches a (query) against b (train): queryIdx indexes a.keypoints, trainIdx b.keypoints.
  // Each query appears at most once. Empty sets, mismatched descriptor types or widths give an
  // empty result. The output is sorted by queryIdx.
  std::vector<cv::DMatch> Match(const FeatureSet& a, const FeatureSet& b) const;

  const MatcherOptions& options() const { return options_; }

 private:
  MatcherOptions options_;
};

// Pixel positions of matched keypoints, in match order: query_points[k] is
// query_keypoints[matches[k].queryIdx], train_points[k] is train_keypoints[matches[k].trainIdx]
// (the point pairs ICGM works on).
void MatchedPoints(const std::vector<cv::KeyPoint>& query_keypoints,
                   const std::vector<cv::KeyPoint>& train_keypoints,
                   const std::vector<cv::DMatch>& matches,
                   std::vector<Eigen::Vector2d>* query_points,
                   std::vector<Eigen::Vector2d>* train_points);

}  // namespace icgm
