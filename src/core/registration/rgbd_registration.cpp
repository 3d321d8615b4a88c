#include "core/registration/rgbd_registration.h"

#include <algorithm>
#include <cmath>
#include <optional>
#include <sstream>

#include "core/common/option_reader.h"
#include "core/registration/pose_refinement.h"
#include "core/registration/ransac_horn.h"

namespace icgm {

void ReadOptions(const OptionReader& reader, RegistrationOptions* options) {
  reader.Read("min_matches_3d", &options->min_matches_3d, 3, 100000);
  reader.Read("min_inliers", &options->min_inliers, 3, 100000);
  reader.Read("min_inlier_ratio", &options->min_inlier_ratio, 0.0, 1.0);
  reader.Read("inlier_threshold_m", &options->inlier_threshold_m, 1e-4, 1.0);
  reader.Read("max_iterations", &options->max_iterations, 1, 1000000);
  reader.Read("ransac_confidence", &options->ransac_confidence, 0.5, 0.999999);
  reader.Read("refine_rounds", &options->refine_rounds, 0, 100);
  reader.Read("ransac_local_optimization", &options->ransac_local_optimization);
  reader.Read("max_translation_m", &options->max_translation_m, 0.0, 100.0);
  reader.Read("max_rotation_deg", &options->max_rotation_deg, 0.0, 180.0);
  int seed = static_cast<int>(options->rng_seed);
  reader.Read("rng_seed", &seed, 0, 2147483647);
  options->rng_seed = static_cast<uint64_t>(seed);
  reader.Read("min_depth_m", &options->depth.min_depth_m, 0.0, 100.0);
  reader.Read("max_depth_m", &options->depth.max_depth_m, 0.0, 100.0);
  reader.Read("max_depth_jump_ratio", &options->depth.max_depth_jump_ratio, 0.0, 10.0);
  if (options->depth.max_depth_m <= options->depth.min_depth_m) {
    throw LoadError(reader.path() + ".max_depth_m must exceed min_depth_m");
  }
  reader.Read("refine_reprojection", &options->refine_reprojection);
  reader.Read("ransac_reprojection_px", &options->ransac_reprojection_px, 0.0, 100.0);
  reader.Read("reprojection_depth_rel_per_m", &options->reprojection_depth_rel_per_m, 0.0, 1.0);
  reader.Read("reprojection_iterations", &options->reprojection_iterations, 0, 1000);
  reader.Read("reprojection_huber_px", &options->reprojection_huber_px, 0.01, 1000.0);
}

RegistrationResult RegisterRgbd(const std::vector<cv::Point2f>& pts_ref, const cv::Mat& depth_ref_m,
                                const std::vector<cv::Point2f>& pts_cur, const cv::Mat& depth_cur_m,
                                const CameraIntrinsics& intrinsics,
                                const RegistrationOptions& options,
                                const std::vector<double>* pixel_sigma_px) {
  RegistrationResult result;
  result.matches_2d = pts_ref.size();
  if (pts_ref.size() != pts_cur.size()) {
    std::ostringstream s;
    s << "match size mismatch: " << pts_ref.size() << " reference vs " << pts_cur.size()
      << " current keypoints";
    result.status = Status::Error(s.str());
    return result;
  }
  if (pixel_sigma_px && pixel_sigma_px->size() != pts_ref.size()) {
    result.status = Status::Error("pixel sigma count differs from the match count");
    return result;
  }
  if (!intrinsics.Valid()) {
    result.status = Status::Error("invalid camera intrinsics");
    return result;
  }
  for (const cv::Mat* d : {&depth_ref_m, &depth_cur_m}) {
    if (d->empty() || d->type() != CV_32FC1) {
      result.status = Status::Error("depth image must be a non-empty CV_32FC1 (metres)");
      return result;
    }
  }

  // 1. 3-D points for the matches with usable depth on both sides.
  std::vector<Eigen::Vector3d> all_ref, all_cur;
  std::vector<uint8_t> ok_ref, ok_cur;
  DepthRejectCounts rej_ref, rej_cur;
  KeypointsToPoints(pts_ref, depth_ref_m, intrinsics, options.depth, &all_ref, &ok_ref, &rej_ref);
  KeypointsToPoints(pts_cur, depth_cur_m, intrinsics, options.depth, &all_cur, &ok_cur, &rej_cur);
  result.depth_rejects = rej_ref;
  result.depth_rejects += rej_cur;

  std::vector<int> index_of;  // 3-D match -> input match index
  std::vector<Eigen::Vector3d> p_ref, p_cur;
  std::vector<cv::Point2f> u_ref, u_cur;
  std::vector<double> sigma;
  for (size_t i = 0; i < pts_ref.size(); ++i) {
    if (!ok_ref[i] || !ok_cur[i]) continue;
    index_of.push_back(static_cast<int>(i));
    p_ref.push_back(all_ref[i]);
    p_cur.push_back(all_cur[i]);
    u_ref.push_back(pts_ref[i]);
    u_cur.push_back(pts_cur[i]);
    if (pixel_sigma_px) sigma.push_back(std::max(1e-3, (*pixel_sigma_px)[i]));
  }
  result.matches_3d = index_of.size();
  if (static_cast<int>(result.matches_3d) < options.min_matches_3d) {
    std::ostringstream s;
    s << "too few 3D matches: " << result.matches_3d << " < " << options.min_matches_3d << " ("
      << result.matches_2d << " 2D matches; depth rejects: " << result.depth_rejects.ToString()
      << ")";
    result.status = Status::Error(s.str());
    return result;
  }

  // 2. RANSAC + Horn, p_ref = T p_cur.
  RansacOptions ransac;
  ransac.inlier_threshold_m = options.inlier_threshold_m;
  ransac.max_iterations = options.max_iterations;
  ransac.confidence = options.ransac_confidence;
  ransac.refine_rounds = options.refine_rounds;
  ransac.min_inliers = options.min_inliers;
  ransac.rng_seed = options.rng_seed;
  ransac.local_optimization = options.ransac_local_optimization;
  std::optional<ReprojectionInlierTest> test;
  if (options.ransac_reprojection_px > 0.0) {
    test.emplace();
    test->intrinsics = intrinsics;
    test->threshold_px = options.ransac_reprojection_px;
    test->depth_abs_m = options.inlier_threshold_m;
    test->depth_rel_per_m = options.reprojection_depth_rel_per_m;
    test->sigma_px = sigma;
    for (size_t k = 0; k < p_cur.size(); ++k) {
      test->src_px.emplace_back(u_cur[k].x, u_cur[k].y);
      test->dst_px.emplace_back(u_ref[k].x, u_ref[k].y);
    }
  }
  const RansacResult r = RansacHorn(p_cur, p_ref, ransac, test ? &*test : nullptr);
  result.relative_pose = r.transform;
  result.inliers = r.inliers.size();
  result.inlier_ratio = static_cast<double>(r.inliers.size()) / result.matches_3d;
  result.rmse_m = r.rmse_m;
  for (int k : r.inliers) result.inlier_indices.push_back(index_of[k]);
  if (!r.status.ok()) {
    result.status = r.status;
    return result;
  }
  if (result.inlier_ratio < options.min_inlier_ratio) {
    std::ostringstream s;
    s << "too few inliers: ratio " << result.inlier_ratio << " < " << options.min_inlier_ratio
      << " (" << result.inliers << " of " << result.matches_3d << ")";
    result.status = Status::Error(s.str());
    return result;
  }

  // 3. Reprojection refinement; falls back to the 3-D covariance if it cannot run.
  Pose3 pose = r.transform;
  bool refined = false;
  if (options.refine_reprojection && options.reprojection_iterations > 0) {
    ReprojectionRefineOptions ro;
    ro.max_iterations = options.reprojection_iterations;
    ro.huber_px = options.reprojection_huber_px;
    refined = RefinePoseByReprojection(p_ref, u_ref, p_cur, u_cur, r.inliers, intrinsics, ro, &pose,
                                       &result.covariance, &result.reprojection_rms_px,
                                       pixel_sigma_px ? &sigma : nullptr)
                  .ok();
  }
  if (!refined) result.covariance = PointToPointCovariance(p_ref, p_cur, r.inliers, pose);
  result.relative_pose = pose;
  double sum_sq = 0.0;
  for (int k : r.inliers) sum_sq += (pose * p_cur[k] - p_ref[k]).squaredNorm();
  result.rmse_m = std::sqrt(sum_sq / r.inliers.size());

  // 4. Plausibility of the motion between the two frames.
  const double trans_m = TranslationNorm(pose);
  const double rot_deg = RotationAngleRad(pose) * 180.0 / M_PI;
  if (trans_m > options.max_translation_m) {
    std::ostringstream s;
    s << "implausible motion: " << trans_m << " m > " << options.max_translation_m << " m";
    result.status = Status::Error(s.str());
  } else if (rot_deg > options.max_rotation_deg) {
    std::ostringstream s;
    s << "implausible motion: " << rot_deg << " deg > " << options.max_rotation_deg << " deg";
    result.status = Status::Error(s.str());
  }
  return result;
}

}  // namespace icgm
