#include "core/common/option_reader.h"
#include "core/odometry/frontend_types.h"

namespace icgm {

void ReadOptions(const OptionReader& reader, FrontendOptions* options) {
  reader.Read("use_icgm", &options->use_icgm);
  reader.Read("max_keyframe_interval_phi", &options->max_keyframe_interval_phi, 1, 100000);
  reader.Read("keyframe_min_inliers", &options->keyframe_min_inliers, 0, 100000);
  reader.Read("keyframe_min_inlier_ratio", &options->keyframe_min_inlier_ratio, 0.0, 1.0);
  reader.Read("keyframe_max_translation_m", &options->keyframe_max_translation_m, 0.0, 100.0);
  reader.Read("keyframe_max_rotation_deg", &options->keyframe_max_rotation_deg, 0.0, 180.0);
  reader.Read("retry_previous_frame", &options->retry_previous_frame);
}

void ReadFrontendOptions(const OptionReader& odometry_root, const OptionReader& icgm_root,
                         FrontendOptions* options) {
  ReadOptions(odometry_root.Section("frontend"), options);
  ReadOptions(odometry_root.Section("registration"), &options->registration);
  ReadOptions(odometry_root.Section("fusion"), &options->fusion);
  ReadOptions(odometry_root.Section("wheel_odometry"), &options->wheel);
  ReadOptions(icgm_root.Section("features"), &options->features);
  ReadOptions(icgm_root.Section("matcher"), &options->matcher);
  ReadOptions(icgm_root.Section("icgm"), &options->icgm);
}

}  // namespace icgm
