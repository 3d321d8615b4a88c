#include "core/features/descriptor_matcher.h"

#include <algorithm>

#include <opencv2/features2d.hpp>
#include <opencv2/flann.hpp>

#include "core/common/option_reader.h"

namespace icgm {

void ReadOptions(const OptionReader& reader, MatcherOptions* options) {
  reader.Read("ratio", &options->ratio, 0.0, 1.0);
  reader.Read("mutual_check", &options->mutual_check);
  reader.ReadChoice("binary_index", &options->binary_index, {"bf", "lsh"});
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
    if (o.binary_index == "lsh") {
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

std::vector<cv::DMatch> DescriptorMatcher::Match(const FeatureSet& a, const FeatureSet& b) const {
  std::vector<cv::DMatch> out;
  if (!Compatible(a, b)) return out;
  // LSH may return fewer than k neighbours per query; all paths below tolerate short lists.
  const bool use_ratio = options_.ratio < 1.0 && b.descriptors.rows >= 2;
  std::vector<std::vector<cv::DMatch>> knn;
  try {
    auto matcher = MakeMatcher(options_, a.binary);
    matcher->knnMatch(a.descriptors, b.descriptors, knn, use_ratio ? 2 : 1);
  } catch (const cv::Exception&) {
    return out;  // e.g. FLANN rejecting a degenerate index; no matches is the honest answer.
  }

  std::vector<int> best_a_for_b;
  if (options_.mutual_check) {
    std::vector<cv::DMatch> reverse;
    try {
      auto matcher = MakeMatcher(options_, a.binary);
      matcher->match(b.descriptors, a.descriptors, reverse);
    } catch (const cv::Exception&) {
      return out;
    }
    best_a_for_b.assign(b.descriptors.rows, -1);
    for (const cv::DMatch& m : reverse) {
      if (m.queryIdx >= 0 && m.queryIdx < b.descriptors.rows) best_a_for_b[m.queryIdx] = m.trainIdx;
    }
  }

  out.reserve(knn.size());
  for (const auto& candidates : knn) {
    if (candidates.empty()) continue;
    const cv::DMatch& best = candidates[0];
    if (best.trainIdx < 0 || best.trainIdx >= b.descriptors.rows) continue;
    if (use_ratio && candidates.size() >= 2 &&
        !(best.distance < options_.ratio * candidates[1].distance)) {
      continue;
    }
    if (options_.max_distance > 0.0 && best.distance > options_.max_distance) continue;
    if (options_.mutual_check && best_a_for_b[best.trainIdx] != best.queryIdx) continue;
    out.push_back(best);
  }
  std::sort(out.begin(), out.end(),
            [](const cv::DMatch& l, const cv::DMatch& r) { return l.queryIdx < r.queryIdx; });
  return out;
}

}  // namespace icgm
