#include "core/slam/nearest_keyframe_localizer.h"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <utility>
#include <vector>

#include "core/map/pose_average.h"

namespace icgm {
namespace {

Mat6 DiagonalCovariance(double sigma_m, double sigma_rad) {
  Vec6 d;
  d << sigma_m * sigma_m, sigma_m * sigma_m, sigma_m * sigma_m, sigma_rad * sigma_rad,
      sigma_rad * sigma_rad, sigma_rad * sigma_rad;
  return d.asDiagonal();
}

std::string Describe(const char* what, double value, double limit, const char* unit) {
  std::ostringstream s;
  s.precision(3);
  s << what << " " << value << unit << " > " << limit << unit;
  return s.str();
}

}  // namespace

Status CheckFixGate(const Pose3& predicted, const Pose3& located, double path_since_fix_m,
                    const FixGateOptions& gate) {
  if (gate.max_m <= 0.0) return Status::Ok();
  const Pose3 diff = Between(predicted, located);
  const double limit_m = gate.max_m + gate.m_per_m * path_since_fix_m;
  if (TranslationNorm(diff) > limit_m) {
    return Status::Error(Describe("fix gate: jump", TranslationNorm(diff), limit_m, " m"));
  }
  const double angle_deg = RotationAngleRad(diff) * 180.0 / M_PI;
  if (angle_deg > gate.max_deg) {
    return Status::Error(Describe("fix gate: turn", angle_deg, gate.max_deg, " deg"));
  }
  return Status::Ok();
}

LoopClosureResult LocateAtNearestKeyframes(const Keyframe& query, const HybridMap& map, int max_id,
                                           const RegisterFn& register_fn,
                                           const NearestKeyframeOptions& options,
                                           const LoopClosureOptions& verification,
                                           const FixGateOptions& gate, double path_since_fix_m) {
  LoopClosureResult result;
  const double radius_rad = options.radius_deg * M_PI / 180.0;
  std::vector<std::pair<double, int>> near;
  for (const Keyframe& kf : map.keyframes()) {
    if (kf.id >= max_id || static_cast<int>(kf.keypoints.size()) < verification.min_inliers) {
      continue;
    }
    const Pose3 d = Between(query.global_pose, kf.global_pose);
    const double t = TranslationNorm(d) / options.radius_m;
    const double r = RotationAngleRad(d) / radius_rad;
    if (t <= 1.0 && r <= 1.0) near.emplace_back(t + r, kf.id);
  }
  if (near.empty()) {
    result.status = Status::Error("no fix: no learned keyframe near the predicted pose");
    return result;
  }
  std::sort(near.begin(), near.end());
  if (static_cast<int>(near.size()) > options.count) near.resize(options.count);
  std::vector<WeightedPose> hypotheses;
  for (const auto& [distance, id] : near) {
    const Keyframe& candidate = map.keyframe(id);
    const RegistrationOutcome outcome = register_fn(query, candidate);
    ++result.registrations;
    LoopEvidence e = MakeLoopEvidence(candidate, 0.0, outcome);
    e.proximity = true;
    if (!outcome.status.ok()) {
      e.rejected = outcome.status.reason();
    } else if (outcome.inliers < verification.min_inliers) {
      e.rejected = "too few inliers";
    } else if (TranslationNorm(outcome.relative_pose) > verification.max_link_translation_m ||
               RotationAngleRad(outcome.relative_pose) > verification.max_link_rad) {
      e.rejected = "registered motion too large for one place";
    } else if (std::string gated = PoseGateRejection(query.global_pose, e.global_pose,
                                                     path_since_fix_m, verification);
               !gated.empty()) {
      e.rejected = std::move(gated);
    } else if (const Status fix_gated =
                   CheckFixGate(query.global_pose, e.global_pose, path_since_fix_m, gate);
               !fix_gated.ok()) {
      e.rejected = fix_gated.reason();
    } else {
      hypotheses.push_back({e.global_pose, outcome.information});
    }
    result.evidence.push_back(std::move(e));
  }
  if (hypotheses.empty()) {
    result.status = Status::Error("no fix: none of the " + std::to_string(near.size()) +
                                  " nearest keyframes registered within the guard (" +
                                  result.evidence.front().rejected + ")");
    return result;
  }
  const Status averaged = AveragePoses(hypotheses, &result.loop_closure_pose);
  if (!averaged.ok()) {
    result.status = Status::Error("no fix: " + averaged.reason());
    return result;
  }
  result.delta_pose_diff = Between(query.global_pose, result.loop_closure_pose);
  result.status = Status::Ok();
  return result;
}

void OdometryFixFilter::Reset(const Mat6& covariance) {
  covariance_ = covariance;
  initialized_ = true;
}

Pose3 OdometryFixFilter::Update(const Pose3& predicted, const Pose3& measured,
                                const Mat6& measurement_information, double path_m) {
  const Mat6 measurement_covariance =
      measurement_information.inverse() +
      DiagonalCovariance(options_.measurement_floor_sigma_m, options_.measurement_floor_sigma_rad);
  if (!initialized_ || !measurement_covariance.allFinite()) {
    Reset(measurement_covariance.allFinite() ? measurement_covariance : Mat6::Identity());
    return measured;
  }
  const Mat6 prediction_covariance =
      covariance_ +
      DiagonalCovariance(options_.floor_sigma_m + options_.sigma_m_per_m * path_m,
                         options_.floor_sigma_rad + options_.sigma_rad_per_m * path_m);
  const Mat6 prediction_information = prediction_covariance.inverse();
  const Mat6 measured_information = measurement_covariance.inverse();
  Pose3 fused = measured;
  const Status averaged =
      AveragePoses({{predicted, prediction_information}, {measured, measured_information}}, &fused);
  if (!averaged.ok()) {
    Reset(measurement_covariance);
    return measured;
  }
  covariance_ = (prediction_information + measured_information).inverse();
  return fused;
}

}  // namespace icgm
