#include "core/odometry/anchor_keyframes.h"

#include <cmath>
#include <cstdio>

namespace icgm {

bool QualifiesAsAnchor(const AnchorOptions& options, int anchors_so_far,
                       const int* registration_inliers) {
  if (options.keyframes <= 0 || anchors_so_far >= options.keyframes) return false;
  if (!registration_inliers) return anchors_so_far == 0;
  return *registration_inliers >= options.keyframe_min_inliers;
}

AnchorCorrection CorrectByAnchor(const Pose3& chained, const Pose3& anchored, int inliers,
                                 const AnchorOptions& options) {
  AnchorCorrection out;
  out.odom_camera = chained;
  char why[160];
  if (inliers < options.min_inliers) {
    std::snprintf(why, sizeof(why), "anchor registration: %d inliers < %d", inliers,
                  options.min_inliers);
    out.status = Status::Error(why);
    return out;
  }
  const Pose3 offset = Between(chained, anchored);
  const double offset_m = TranslationNorm(offset);
  const double offset_deg = RotationAngleRad(offset) * 180.0 / M_PI;
  if ((options.max_correction_m > 0.0 && offset_m > options.max_correction_m) ||
      (options.max_correction_deg > 0.0 && offset_deg > options.max_correction_deg)) {
    std::snprintf(
        why, sizeof(why),
        "anchor estimate %.3f m / %.2f deg from the chained one, beyond %.3f m / %.2f deg",
        offset_m, offset_deg, options.max_correction_m, options.max_correction_deg);
    out.status = Status::Error(why);
    return out;
  }
  const Vec6 delta = LogSE3(offset);
  if (!delta.allFinite()) {
    out.status = Status::Error("anchor correction: not finite");
    return out;
  }
  out.odom_camera = Orthonormalized(chained * ExpSE3(options.gain * delta));
  return out;
}

}  // namespace icgm
