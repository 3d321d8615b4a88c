#include "core/map/keyframe_registration.h"

#include <cmath>
#include <string>
#include <vector>

#include "core/common/option_reader.h"

namespace icgm {

void ReadOptions(const OptionReader& icgm_root, const OptionReader& map_root,
                 KeyframeRegistrationOptions* o, std::vector<std::string>* unused_keys) {
  ReadOptions(icgm_root.Section("matcher"), &o->matcher);
  ReadOptions(icgm_root.Section("icgm"), &o->icgm);
  const OptionReader r = map_root.Section("loop_closure").Section("registration");
  r.Read("use_icgm", &o->use_icgm);
  r.Read("inlier_threshold_m", &o->ransac.inlier_threshold_m, 1e-4, 10.0);
  r.Read("max_iterations", &o->ransac.max_iterations, 1, 1000000);
  r.Read("min_inliers", &o->ransac.min_inliers, 3, 1000000);
  r.Read("max_translation_m", &o->max_translation_m, 0.0, 1e6);
  r.Read("max_rotation_rad", &o->max_rotation_rad, 0.0, 3.2);
  if (unused_keys) *unused_keys = r.UnusedKeys();
}

RegistrationOutcome RegisterKeyframes(const Keyframe& query, const Keyframe& candidate,
                                      const KeyframeRegistrationOptions& options) {
  RegistrationOutcome out;
  FeatureSet a;
  a.keypoints = query.keypoints;
  a.descriptors = query.descriptors;
  a.binary = query.binary();
  FeatureSet b;
  b.keypoints = candidate.keypoints;
  b.descriptors = candidate.descriptors;
  b.binary = candidate.binary();
  if (a.empty() || b.empty()) {
    out.status = Status::Error("registration rejected: a model has no features");
    return out;
  }
  const std::vector<cv::DMatch> matches = DescriptorMatcher(options.matcher).Match(a, b);
  std::vector<uint8_t> kept(matches.size(), 1);
  if (options.use_icgm && matches.size() >= 2) {
    std::vector<Eigen::Vector2d> pa;
    std::vector<Eigen::Vector2d> pb;
    for (const auto& m : matches) {
      pa.emplace_back(a.keypoints[m.queryIdx].pt.x, a.keypoints[m.queryIdx].pt.y);
      pb.emplace_back(b.keypoints[m.trainIdx].pt.x, b.keypoints[m.trainIdx].pt.y);
    }
    const IcgmResult icgm = RunIcgm(pa, pb, options.icgm);
    if (!icgm.status.ok()) {
      out.status = Status::Error("registration rejected: ICGM: " + icgm.status.reason());
      return out;
    }
    kept = icgm.kept;
  }
  std::vector<Eigen::Vector3d> src;  // query camera frame
  std::vector<Eigen::Vector3d> dst;  // candidate camera frame
  for (size_t i = 0; i < matches.size(); ++i) {
    if (!kept[i]) continue;
    const Eigen::Vector3d& p = query.points_m[matches[i].queryIdx];
    const Eigen::Vector3d& q = candidate.points_m[matches[i].trainIdx];
    if (!p.allFinite() || !q.allFinite()) continue;
    src.push_back(p);
    dst.push_back(q);
  }
  if (static_cast<int>(src.size()) < options.ransac.min_inliers) {
    out.status =
        Status::Error("registration rejected: too few 3D matches: " + std::to_string(src.size()) +
                      " < " + std::to_string(options.ransac.min_inliers));
    return out;
  }
  const RansacResult ransac = RansacHorn(src, dst, options.ransac);
  out.inliers = static_cast<int>(ransac.inliers.size());
  if (!ransac.status.ok()) {
    out.status = Status::Error("registration rejected: " + ransac.status.reason());
    return out;
  }
  out.relative_pose = ransac.transform;
  const double t = TranslationNorm(ransac.transform);
  const double r = RotationAngleRad(ransac.transform);
  if (t > options.max_translation_m || r > options.max_rotation_rad) {
    out.status = Status::Error("registration rejected: implausible loop pose " + std::to_string(t) +
                               " m, " + std::to_string(r) + " rad");
    return out;
  }
  Eigen::Vector3d centroid = Eigen::Vector3d::Zero();
  for (int i : ransac.inliers) centroid += src[i];
  centroid /= static_cast<double>(ransac.inliers.size());
  double spread2 = 0.0;
  for (int i : ransac.inliers) spread2 += (src[i] - centroid).squaredNorm();
  spread2 = std::max(spread2 / ransac.inliers.size(), 1e-4);
  const double sigma_t =
      std::max(options.min_sigma_m, ransac.rmse_m / std::sqrt(static_cast<double>(out.inliers)));
  const double info_t = 1.0 / (sigma_t * sigma_t);
  out.information = Mat6::Zero();
  out.information.diagonal() << info_t, info_t, info_t, info_t * spread2, info_t * spread2,
      info_t * spread2;
  out.status = Status::Ok();
  return out;
}

RegisterFn MakeKeyframeRegisterFn(const KeyframeRegistrationOptions& options) {
  return [options](const Keyframe& query, const Keyframe& candidate) {
    return RegisterKeyframes(query, candidate, options);
  };
}

}  // namespace icgm
