#include "core/odometry/registration_agreement.h"

#include <Eigen/Cholesky>
#include <algorithm>
#include <cmath>

namespace icgm {

std::optional<RegistrationAgreement> CompareRegistrations(
    const std::vector<PoseLink>& links, const RegistrationAgreementOptions& options) {
  using Vec6d = Eigen::Matrix<double, 6, 1>;
  if (links.empty() || static_cast<int>(links.size()) < std::max(2, options.min_registrations)) {
    return std::nullopt;
  }
  // Information-weighted mean in the tangent space at the first link (one Gauss-Newton step
  // suffices for estimates millimetres apart).
  const Pose3& origin = links.front().odom_camera;
  Mat6 info_sum = Mat6::Zero();
  Vec6d weighted = Vec6d::Zero();
  for (const PoseLink& link : links) {
    Eigen::LDLT<Mat6> ldlt(link.covariance);
    const Vec6d delta = LogSE3(Between(origin, link.odom_camera));
    if (ldlt.info() != Eigen::Success || !link.covariance.allFinite() || !delta.allFinite()) {
      return std::nullopt;
    }
    const Mat6 info = ldlt.solve(Mat6::Identity());
    info_sum += info;
    weighted += info * delta;
  }
  Eigen::LDLT<Mat6> sum_ldlt(info_sum);
  const Vec6d mean_delta = sum_ldlt.solve(weighted);
  if (sum_ldlt.info() != Eigen::Success || !mean_delta.allFinite()) return std::nullopt;
  RegistrationAgreement out;
  out.mean = Orthonormalized(origin * ExpSE3(mean_delta));
  Vec6d variance = Vec6d::Zero();
  for (const PoseLink& link : links) {
    const Pose3 d = Between(out.mean, link.odom_camera);
    out.spread_m = std::max(out.spread_m, TranslationNorm(d));
    out.spread_deg = std::max(out.spread_deg, RotationAngleRad(d) * 180.0 / M_PI);
    variance += LogSE3(d).cwiseAbs2();
  }
  out.agree = out.spread_m <= options.max_m && out.spread_deg <= options.max_deg;
  variance /= static_cast<double>(links.size() - 1);
  out.covariance = options.covariance_scale * sum_ldlt.solve(Mat6::Identity());
  out.covariance.diagonal() += options.spread_weight * variance;
  return out;
}

}  // namespace icgm
