#include "core/slam/keyframe_conversion.h"

#include <algorithm>
#include <cstdint>
#include <vector>

namespace icgm {

RelativePoseSource ToRelativePoseSource(MotionSource source) {
  return source == MotionSource::kVision ? RelativePoseSource::kVisual
                                         : RelativePoseSource::kWheelOdometry;
}

Keyframe ToMapKeyframe(const FrontendKeyframe& keyframe,
                       const std::optional<Pose3>& previous_odom_camera,
                       const Pose3& session_from_odom, const KeyframeConversionOptions& options) {
  Keyframe out;
  out.stamp = keyframe.stamp;
  if (previous_odom_camera) {
    out.relative_pose = Orthonormalized(Between(*previous_odom_camera, keyframe.odom_camera));
    out.relative_source = ToRelativePoseSource(keyframe.relative_source);
  } else {
    out.relative_pose = Orthonormalized(session_from_odom * keyframe.odom_camera);
    out.relative_source = RelativePoseSource::kSessionStart;
  }

  const FeatureSet& features = keyframe.features;
  const size_t n = features.keypoints.size();
  const bool any_robust =
      std::any_of(keyframe.robust.begin(), keyframe.robust.end(), [](uint8_t r) { return r; });
  const bool keep_all = !options.robust_only || (!any_robust && options.keep_all_without_reference);
  std::vector<int> rows;
  for (size_t i = 0; i < n; ++i) {
    const bool robust = i < keyframe.robust.size() && keyframe.robust[i];
    const bool has_point = i < keyframe.points_m.size() && keyframe.points_m[i].allFinite();
    const bool has_descriptor = static_cast<int>(i) < features.descriptors.rows;
    if ((robust || keep_all) && has_point && has_descriptor) rows.push_back(static_cast<int>(i));
  }
  out.keypoints.reserve(rows.size());
  out.points_m.reserve(rows.size());
  const int type = features.descriptors.empty() ? (features.binary ? CV_8U : CV_32F)
                                                : features.descriptors.type();
  out.descriptors.create(static_cast<int>(rows.size()), features.descriptors.cols, type);
  for (size_t k = 0; k < rows.size(); ++k) {
    const int i = rows[k];
    out.keypoints.push_back(features.keypoints[i]);
    out.points_m.push_back(keyframe.points_m[i]);
    features.descriptors.row(i).copyTo(out.descriptors.row(static_cast<int>(k)));
  }
  return out;
}

}  // namespace icgm
