// Geometric verification of a loop hypothesis between two images (iBoW-LCD, FAB-MAP 2.0 and
// PIRF-nav evaluations do the same): features are matched by descriptor (Lowe's ratio test,
// mutual check), then RANSAC fits the epipolar geometry: the essential matrix (five-point
// algorithm, Nister 2004) when the camera intrinsics are known, the fundamental matrix (eight
// points) otherwise. A look-alike place shares descriptors but not one rigid scene, so few of
// its matches fit one epipolar geometry. An RGB-D system verifies loops by 6D registration
// instead (core/map/loop_closure.h).
#pragma once

#include <limits>
#include <optional>
#include <vector>

#include <Eigen/Core>

#include "core/common/camera.h"
#include "core/common/status.h"
#include "core/features/feature_extractor.h"
#include "core/place/place_options.h"

namespace icgm {

struct GeometricCheck {
  Status status = Status::Error("not verified");  // ok: the loop is geometrically consistent
  int matches = 0;                                // putative descriptor matches
  int inliers = 0;                                // of those, fitting the epipolar geometry
  // VerifyRigid only (NaN otherwise): the fitted motion between the two cameras.
  double translation_m = std::numeric_limits<double>::quiet_NaN();
  double rotation_deg = std::numeric_limits<double>::quiet_NaN();
};

// The epipolar RANSAC alone, on correspondences a[k] <-> b[k] (pixels). `intrinsics`: the
// camera of both images (essential matrix), or nullopt (fundamental matrix). Never throws; the
// reason of a rejection names the counts.
GeometricCheck VerifyEpipolar(const std::vector<cv::Point2f>& a, const std::vector<cv::Point2f>& b,
                              const GeometricVerificationOptions& options,
                              const std::optional<CameraIntrinsics>& intrinsics);

// RGB-D check on 3-D correspondences query[k] <-> candidate[k] (each in its camera's frame,
// metres): RANSAC + Horn (core/registration/ransac_horn.h) for one rigid motion, at least
// options.min_inliers within options.rgbd_inlier_m; when it passes, the fitted motion's size is
// returned too. Never throws; a rejection names the counts.
GeometricCheck VerifyRigid(const std::vector<Eigen::Vector3d>& query,
                           const std::vector<Eigen::Vector3d>& candidate,
                           const GeometricVerificationOptions& options);

// Descriptor matching, then VerifyRigid on the matches with a 3-D point on both sides
// (`*_points_m`: one per keypoint, NaN where none; a size mismatch gives no matches).
GeometricCheck VerifyRigidGeometry(const FeatureSet& query,
                                   const std::vector<Eigen::Vector3d>& query_points_m,
                                   const FeatureSet& candidate,
                                   const std::vector<Eigen::Vector3d>& candidate_points_m,
                                   const GeometricVerificationOptions& options);

// Descriptor matching, then VerifyEpipolar.
GeometricCheck VerifyGeometry(const FeatureSet& query, const FeatureSet& candidate,
                              const GeometricVerificationOptions& options,
                              const std::optional<CameraIntrinsics>& intrinsics);

}  // namespace icgm
