#include "core/place/geometric_verification.h"

#include <algorithm>
#include <string>
#include <vector>

#include <opencv2/calib3d.hpp>

#include "core/features/descriptor_matcher.h"

namespace icgm {

GeometricCheck VerifyEpipolar(const std::vector<cv::Point2f>& a, const std::vector<cv::Point2f>& b,
                              const GeometricVerificationOptions& options,
                              const std::optional<CameraIntrinsics>& intrinsics) {
  GeometricCheck out;
  out.matches = static_cast<int>(std::min(a.size(), b.size()));
  const int needed = std::max(options.min_inliers, 8);
  if (a.size() != b.size() || out.matches < needed) {
    out.status = Status::Error("geometric verification: " + std::to_string(out.matches) +
                               " matches < " + std::to_string(needed));
    return out;
  }
  cv::Mat mask;
  try {
    if (intrinsics) {
      const cv::Mat k = (cv::Mat_<double>(3, 3) << intrinsics->fx_px, 0.0, intrinsics->cx_px, 0.0,
                         intrinsics->fy_px, intrinsics->cy_px, 0.0, 0.0, 1.0);
      cv::findEssentialMat(a, b, k, cv::RANSAC, options.ransac_confidence,
                           options.ransac_threshold_px, mask);
    } else {
      cv::findFundamentalMat(a, b, cv::FM_RANSAC, options.ransac_threshold_px,
                             options.ransac_confidence, mask);
    }
  } catch (const cv::Exception& e) {
    out.status = Status::Error(std::string("geometric verification: ") + e.what());
    return out;
  }
  out.inliers = mask.empty() ? 0 : cv::countNonZero(mask);
  if (out.inliers < options.min_inliers) {
    out.status = Status::Error("geometric verification: " + std::to_string(out.inliers) +
                               " inliers < " + std::to_string(options.min_inliers) + " of " +
                               std::to_string(out.matches) + " matches");
    return out;
  }
  out.status = Status::Ok();
  return out;
}

GeometricCheck VerifyGeometry(const FeatureSet& query, const FeatureSet& candidate,
                              const GeometricVerificationOptions& options,
                              const std::optional<CameraIntrinsics>& intrinsics) {
  MatcherOptions matcher_options;
  matcher_options.ratio = options.ratio;
  matcher_options.mutual_check = true;
  const std::vector<cv::DMatch> matches =
      DescriptorMatcher(matcher_options).Match(query, candidate);
  std::vector<cv::Point2f> a, b;
  a.reserve(matches.size());
  b.reserve(matches.size());
  for (const cv::DMatch& m : matches) {
    a.push_back(query.keypoints[static_cast<size_t>(m.queryIdx)].pt);
    b.push_back(candidate.keypoints[static_cast<size_t>(m.trainIdx)].pt);
  }
  return VerifyEpipolar(a, b, options, intrinsics);
}

}  // namespace icgm
