#include "core/features/descriptor_matcher.h"

#include <algorithm>
#include <climits>
#include <cmath>
#include <cstdint>
#include <limits>

#include <opencv2/features2d.hpp>
#include <opencv2/flann.hpp>

#include "core/common/option_reader.h"
#include "core/features/hamming_knn.h"

namespace icgm {

void ReadOptions(const OptionReader& reader, MatcherOptions* options) {
  reader.Read("ratio", &options->ratio, 0.0, 1.0);
  reader.Read("mutual_check", &options->mutual_check);
  reader.ReadEnum("binary_index", &options->binary_index);
  reader.Read("flann_trees", &options->flann_trees, 1, 64);
  reader.Read("flann_checks", &options->flann_checks, 1, 100000);
  reader.Read("lsh_tables", &options->lsh_tables, 1, 64);
  reader.Read("lsh_key_bits", &options->lsh_key_bits, 4, 32);
  reader.Read("lsh_probe_level", &options->lsh_probe_level, 0, 4);
  reader.Read("max_distance", &options->max_distance, -1.0, 1e9);
}

DescriptorMatcher::DescriptorMatcher(const MatcherOptions& options) : options_(options) {}

namespace {

cv::Ptr<cv::DescriptorMatcher> MakeMatcher(const MatcherOptions& o, bool binary) {
  if (binary) {
    if (o.binary_index == BinaryIndex::kLsh) {
      return cv::makePtr<cv::FlannBasedMatcher>(
          cv::makePtr<cv::flann::LshIndexParams>(o.lsh_tables, o.lsh_key_bits, o.lsh_probe_level),
          cv::makePtr<cv::flann::SearchParams>(-1));
    }
    return cv::makePtr<cv::BFMatcher>(cv::NORM_HAMMING, false);
  }
  return cv::makePtr<cv::FlannBasedMatcher>(
      cv::makePtr<cv::flann::KDTreeIndexParams>(o.flann_trees),
      cv::makePtr<cv::flann::SearchParams>(o.flann_checks));
}

// FLANN's randomized kd-trees and LSH tables draw from OpenCV's per-thread generator, whose
// state depends on what that thread ran before: the same two frames matched on another thread
// (a nodelet's) or after other work gave other matches than icgm_slam_offline. Each match runs
// from the same seed, and the thread's generator is given back afterwards.
class FixedFlannSeed {
 public:
  FixedFlannSeed() : saved_(cv::theRNG()) { cv::theRNG() = cv::RNG(kSeed); }
  ~FixedFlannSeed() { cv::theRNG() = saved_; }
  FixedFlannSeed(const FixedFlannSeed&) = delete;
  FixedFlannSeed& operator=(const FixedFlannSeed&) = delete;

 private:
  static constexpr uint64_t kSeed = 0x1c9e5eedULL;
  cv::RNG saved_;
};

bool Compatible(const FeatureSet& a, const FeatureSet& b) {
  if (a.descriptors.empty() || b.descriptors.empty()) return false;
  if (a.descriptors.type() != b.descriptors.type()) return false;
  if (a.descriptors.cols != b.descriptors.cols) return false;
  if (a.descriptors.rows != static_cast<int>(a.keypoints.size())) return false;
  if (b.descriptors.rows != static_cast<int>(b.keypoints.size())) return false;
  const int expected = a.binary ? CV_8U : CV_32F;
  return a.binary == b.binary && a.descriptors.depth() == expected && a.descriptors.channels() == 1;
}

}  // namespace

namespace {

// Ratio test, distance gate and mutual check over per-query candidate lists.
struct Candidate {
  int query;
  int train;
  float distance;
  float second;  // +inf when unknown
};

std::vector<cv::DMatch> Filter(const MatcherOptions& o, const std::vector<Candidate>& candidates,
                               const std::vector<int>& best_a_for_b) {
  std::vector<cv::DMatch> out;
  out.reserve(candidates.size());
  const bool use_ratio = o.ratio < 1.0;
  for (const Candidate& c : candidates) {
    if (c.train < 0) continue;
    if (use_ratio && std::isfinite(c.second) && !(c.distance < o.ratio * c.second)) continue;
    if (o.max_distance > 0.0 && c.distance > o.max_distance) continue;
    if (o.mutual_check && best_a_for_b[c.train] != c.query) continue;
    out.emplace_back(c.query, c.train, c.distance);
  }
  return out;
}

}  // namespace

std::vector<cv::DMatch> DescriptorMatcher::Match(const FeatureSet& a, const FeatureSet& b) const {
  if (!Compatible(a, b)) return {};
  const float inf = std::numeric_limits<float>::infinity();
  std::vector<Candidate> candidates;
  candidates.reserve(a.descriptors.rows);
  std::vector<int> best_a_for_b;
  if (options_.mutual_check) best_a_for_b.assign(b.descriptors.rows, -1);

  if (a.binary && options_.binary_index == BinaryIndex::kBruteForce) {
    std::vector<HammingKnn2> knn;
    if (!HammingKnn2Search(a.descriptors, b.descriptors, &knn)) return {};
    for (int q = 0; q < static_cast<int>(knn.size()); ++q) {
      const HammingKnn2& k = knn[q];
      candidates.push_back(
          {q, k.best, static_cast<float>(k.best_distance),
           k.second_distance == INT_MAX ? inf : static_cast<float>(k.second_distance)});
    }
    if (options_.mutual_check) {
      if (!HammingKnn2Search(b.descriptors, a.descriptors, &knn)) return {};
      for (int t = 0; t < static_cast<int>(knn.size()); ++t) best_a_for_b[t] = knn[t].best;
    }
    return Filter(options_, candidates, best_a_for_b);
  }

  // FLANN (kd-tree for float, LSH for binary). LSH may return fewer than k neighbours per
  // query; a query without a second neighbour skips the ratio test.
  const int k = b.descriptors.rows >= 2 ? 2 : 1;
  std::vector<std::vector<cv::DMatch>> knn;
  try {
    {
      const FixedFlannSeed seed;
      MakeMatcher(options_, a.binary)->knnMatch(a.descriptors, b.descriptors, knn, k);
    }
    if (options_.mutual_check) {
      const FixedFlannSeed seed;
      std::vector<cv::DMatch> reverse;
      MakeMatcher(options_, a.binary)->match(b.descriptors, a.descriptors, reverse);
      for (const cv::DMatch& m : reverse) {
        if (m.queryIdx >= 0 && m.queryIdx < b.descriptors.rows) {
          best_a_for_b[m.queryIdx] = m.trainIdx;
        }
      }
    }
  } catch (const cv::Exception&) {
    return {};  // e.g. FLANN rejecting a degenerate index; no matches is the honest answer.
  }
  for (const auto& list : knn) {
    if (list.empty()) continue;
    const cv::DMatch& best = list[0];
    if (best.trainIdx < 0 || best.trainIdx >= b.descriptors.rows) continue;
    candidates.push_back(
        {best.queryIdx, best.trainIdx, best.distance, list.size() >= 2 ? list[1].distance : inf});
  }
  std::vector<cv::DMatch> out = Filter(options_, candidates, best_a_for_b);
  std::sort(out.begin(), out.end(),
            [](const cv::DMatch& l, const cv::DMatch& r) { return l.queryIdx < r.queryIdx; });
  return out;
}

void MatchedPoints(const std::vector<cv::KeyPoint>& query_keypoints,
                   const std::vector<cv::KeyPoint>& train_keypoints,
                   const std::vector<cv::DMatch>& matches,
                   std::vector<Eigen::Vector2d>* query_points,
                   std::vector<Eigen::Vector2d>* train_points) {
  query_points->clear();
  train_points->clear();
  query_points->reserve(matches.size());
  train_points->reserve(matches.size());
  for (const cv::DMatch& m : matches) {
    const cv::Point2f& q = query_keypoints[m.queryIdx].pt;
    const cv::Point2f& t = train_keypoints[m.trainIdx].pt;
    query_points->emplace_back(q.x, q.y);
    train_points->emplace_back(t.x, t.y);
  }
}

}  // namespace icgm
