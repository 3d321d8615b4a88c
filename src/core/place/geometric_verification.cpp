#include "core/place/geometric_verification.h"

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include <Eigen/Geometry>
#include <opencv2/calib3d.hpp>

#include "core/features/descriptor_matcher.h"
#include "core/registration/ransac_horn.h"

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

GeometricCheck VerifyRigid(const std::vector<Eigen::Vector3d>& query,
                           const std::vector<Eigen::Vector3d>& candidate,
                           const GeometricVerificationOptions& options) {
  GeometricCheck out;
  out.matches = static_cast<int>(std::min(query.size(), candidate.size()));
  const int needed = std::max(options.min_inliers, 3);
  if (query.size() != candidate.size() || out.matches < needed) {
    out.status = Status::Error("rgbd verification: " + std::to_string(out.matches) +
                               " 3-D matches < " + std::to_string(needed));
    return out;
  }
  RansacOptions ransac;
  ransac.inlier_threshold_m = options.rgbd_inlier_m;
  ransac.max_iterations = options.rgbd_max_iterations;
  ransac.confidence = options.ransac_confidence;
  ransac.min_inliers = options.min_inliers;
  const RansacResult fit = RansacHorn(candidate, query, ransac);
  out.inliers = static_cast<int>(fit.inliers.size());
  if (fit.status.ok()) {
    out.translation_m = fit.transform.translation().norm();
    out.rotation_deg = Eigen::AngleAxisd(fit.transform.rotation()).angle() * 180.0 / M_PI;
  }
  if (!fit.status.ok()) {
    out.status = Status::Error("rgbd verification: " + fit.status.reason() + " of " +
                               std::to_string(out.matches) + " 3-D matches");
    return out;
  }
  out.status = Status::Ok();
  return out;
}

namespace {

std::vector<cv::DMatch> RatioMatches(const FeatureSet& query, const FeatureSet& candidate,
                                     const GeometricVerificationOptions& options) {
  MatcherOptions matcher_options;
  matcher_options.ratio = options.ratio;
  matcher_options.mutual_check = true;
  return DescriptorMatcher(matcher_options).Match(query, candidate);
}

}  // namespace

GeometricCheck VerifyRigidGeometry(const FeatureSet& query,
                                   const std::vector<Eigen::Vector3d>& query_points_m,
                                   const FeatureSet& candidate,
                                   const std::vector<Eigen::Vector3d>& candidate_points_m,
                                   const GeometricVerificationOptions& options) {
  std::vector<Eigen::Vector3d> a, b;
  if (query_points_m.size() == query.size() && candidate_points_m.size() == candidate.size()) {
    for (const cv::DMatch& m : RatioMatches(query, candidate, options)) {
      const Eigen::Vector3d& p = query_points_m[static_cast<size_t>(m.queryIdx)];
      const Eigen::Vector3d& q = candidate_points_m[static_cast<size_t>(m.trainIdx)];
      if (p.allFinite() && q.allFinite()) {
        a.push_back(p);
        b.push_back(q);
      }
    }
  }
  return VerifyRigid(a, b, options);
}

GeometricCheck VerifyGeometry(const FeatureSet& query, const FeatureSet& candidate,
                              const GeometricVerificationOptions& options,
                              const std::optional<CameraIntrinsics>& intrinsics) {
  const std::vector<cv::DMatch> matches = RatioMatches(query, candidate, options);
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
