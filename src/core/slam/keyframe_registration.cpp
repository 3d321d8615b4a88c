#include "core/slam/keyframe_registration.h"

#include <algorithm>
#include <string>
#include <vector>

#include "core/common/option_reader.h"

namespace icgm {

void ReadOptions(const OptionReader& reader, LoopRegistrationOptions* o) {
  reader.Read("ratio", &o->matcher.ratio, 0.0, 1.0);
  reader.Read("use_icgm", &o->use_icgm);
  reader.Read("icgm_threshold", &o->icgm.threshold, 0.0, 1.0);
  reader.Read("icgm_seed_pairs", &o->icgm.seed_pairs, 1, 1000);
  reader.Read("min_matches", &o->min_matches, 3, 100000);
  reader.Read("inlier_threshold_m", &o->ransac.inlier_threshold_m, 1e-4, 1.0);
  reader.Read("max_iterations", &o->ransac.max_iterations, 1, 1000000);
  reader.Read("ransac_confidence", &o->ransac.confidence, 0.5, 0.999999);
  reader.Read("min_inliers", &o->ransac.min_inliers, 3, 100000);
  reader.Read("min_inlier_ratio", &o->min_inlier_ratio, 0.0, 1.0);
  reader.Read("refine_reprojection", &o->refine_reprojection);
  reader.Read("reprojection_iterations", &o->refine.max_iterations, 0, 1000);
  reader.Read("reprojection_huber_px", &o->refine.huber_px, 0.01, 100.0);
  reader.Read("octave_scale_factor", &o->octave_scale_factor, 0.0, 10.0);
  reader.Read("min_sigma_m", &o->min_sigma_m, 1e-6, 10.0);
  reader.Read("min_sigma_rad", &o->min_sigma_rad, 1e-6, 10.0);
}

KeyframeRegistration::KeyframeRegistration(const LoopRegistrationOptions& options,
                                           const CameraIntrinsics& intrinsics)
    : options_(options), intrinsics_(intrinsics), matcher_(options.matcher) {}

RegisterFn KeyframeRegistration::AsRegisterFn() const {
  return [this](const Keyframe& query, const Keyframe& candidate) {
    return Register(query, candidate);
  };
}

namespace {

FeatureSet AsFeatureSet(const Keyframe& keyframe) {
  FeatureSet set;
  set.keypoints = keyframe.keypoints;
  set.descriptors = keyframe.descriptors;
  set.binary = keyframe.binary();
  return set;
}

bool Consistent(const Keyframe& k) {
  return static_cast<size_t>(k.descriptors.rows) == k.keypoints.size() &&
         k.points_m.size() == k.keypoints.size();
}

RegistrationOutcome Rejected(const std::string& why) {
  RegistrationOutcome out;
  out.status = Status::Error(why);
  return out;
}

std::string TooFew(const char* what, size_t have, int need) {
  return std::string("too few ") + what + ": " + std::to_string(have) + " < " +
         std::to_string(need);
}

}  // namespace

RegistrationOutcome KeyframeRegistration::Register(const Keyframe& query,
                                                   const Keyframe& candidate) const {
  if (!Consistent(query) || !Consistent(candidate)) {
    return Rejected("keyframe keypoint, descriptor and point counts differ");
  }
  if (query.keypoints.empty() || candidate.keypoints.empty()) return Rejected("no features");
  if (query.binary() != candidate.binary() ||
      query.descriptors.cols != candidate.descriptors.cols) {
    return Rejected("descriptor types differ");
  }
  // Candidate is image I_0 (queryIdx), query is I_1 (trainIdx).
  const std::vector<cv::DMatch> matches =
      matcher_.Match(AsFeatureSet(candidate), AsFeatureSet(query));
  std::vector<const cv::DMatch*> usable;
  for (const cv::DMatch& m : matches) {
    if (candidate.points_m[m.queryIdx].allFinite() && query.points_m[m.trainIdx].allFinite()) {
      usable.push_back(&m);
    }
  }
  if (static_cast<int>(usable.size()) < options_.min_matches) {
    return Rejected(TooFew("3D matches", usable.size(), options_.min_matches));
  }

  std::vector<uint8_t> keep(usable.size(), 1);
  if (options_.use_icgm) {
    std::vector<Eigen::Vector2d> pa, pb;
    pa.reserve(usable.size());
    pb.reserve(usable.size());
    for (const cv::DMatch* m : usable) {
      const cv::Point2f& u = candidate.keypoints[m->queryIdx].pt;
      const cv::Point2f& v = query.keypoints[m->trainIdx].pt;
      pa.emplace_back(u.x, u.y);
      pb.emplace_back(v.x, v.y);
    }
    const IcgmResult icgm = RunIcgm(pa, pb, options_.icgm);
    if (!icgm.status.ok()) return Rejected("ICGM: " + icgm.status.reason());
    keep = icgm.kept;
  }
  std::vector<Eigen::Vector3d> src, dst;  // query points, candidate points
  std::vector<cv::Point2f> px_query, px_candidate;
  std::vector<double> sigma_px;
  std::vector<std::pair<int, int>> kept_pairs;  // (query, candidate) keypoint of each kept match
  for (size_t i = 0; i < usable.size(); ++i) {
    if (!keep[i]) continue;
    kept_pairs.emplace_back(usable[i]->trainIdx, usable[i]->queryIdx);
    src.push_back(query.points_m[usable[i]->trainIdx]);
    dst.push_back(candidate.points_m[usable[i]->queryIdx]);
    px_query.push_back(query.keypoints[usable[i]->trainIdx].pt);
    px_candidate.push_back(candidate.keypoints[usable[i]->queryIdx].pt);
    sigma_px.push_back(std::max(
        PyramidPixelSigma(query.keypoints[usable[i]->trainIdx], options_.octave_scale_factor),
        PyramidPixelSigma(candidate.keypoints[usable[i]->queryIdx], options_.octave_scale_factor)));
  }
  if (static_cast<int>(src.size()) < options_.min_matches) {
    return Rejected(TooFew("ICGM matches", src.size(), options_.min_matches));
  }

  const RansacResult ransac = RansacHorn(src, dst, options_.ransac);
  if (!ransac.status.ok()) return Rejected("RANSAC: " + ransac.status.reason());
  const double ratio = static_cast<double>(ransac.inliers.size()) / src.size();
  if (ratio < options_.min_inlier_ratio) {
    return Rejected("inlier ratio " + std::to_string(ratio) + " < " +
                    std::to_string(options_.min_inlier_ratio));
  }

  RegistrationOutcome out;
  out.relative_pose = ransac.transform;
  out.inliers = static_cast<int>(ransac.inliers.size());
  out.inlier_matches.reserve(ransac.inliers.size());
  for (int k : ransac.inliers) out.inlier_matches.push_back(kept_pairs[k]);
  Mat6 covariance = PointToPointCovariance(dst, src, ransac.inliers, ransac.transform);
  if (options_.refine_reprojection && intrinsics_.Valid()) {
    Pose3 refined = ransac.transform;
    Mat6 refined_covariance;
    double rms_px = 0.0;
    const Status s = RefinePoseByReprojection(dst, px_candidate, src, px_query, ransac.inliers,
                                              intrinsics_, options_.refine, &refined,
                                              &refined_covariance, &rms_px, &sigma_px);
    if (s.ok() && refined.matrix().allFinite() && refined_covariance.allFinite()) {
      out.relative_pose = refined;
      covariance = refined_covariance;
    }
  }
  // Floor the uncertainty, then invert.
  const double floor_m = options_.min_sigma_m * options_.min_sigma_m;
  const double floor_rad = options_.min_sigma_rad * options_.min_sigma_rad;
  if (!covariance.allFinite()) covariance = Mat6::Identity();
  for (int i = 0; i < 6; ++i) covariance(i, i) += i < 3 ? floor_m : floor_rad;
  out.information = covariance.inverse();
  if (!out.information.allFinite()) return Rejected("singular registration covariance");
  out.relative_pose = Orthonormalized(out.relative_pose);
  out.status = Status::Ok();
  return out;
}

}  // namespace icgm
