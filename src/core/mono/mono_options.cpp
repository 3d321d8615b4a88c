#include "core/mono/mono_options.h"

#include "core/common/option_reader.h"

namespace icgm {

void ReadOptions(const OptionReader& r, MonoVoOptions* o) {
  r.Read("use_icgm", &o->use_icgm);
  r.Read("min_features", &o->min_features, 5, 1000000);
  r.Read("init_min_matches", &o->init_min_matches, 8, 1000000);
  r.Read("init_min_parallax_deg", &o->init_min_parallax_deg, 0.0, 90.0);
  r.Read("init_min_points", &o->init_min_points, 8, 1000000);
  r.Read("init_max_frames", &o->init_max_frames, 1, 100000);
  r.Read("essential_threshold_px", &o->essential_threshold_px, 0.01, 100.0);
  r.Read("essential_confidence", &o->essential_confidence, 0.5, 0.999999);
  r.Read("ransac_order_seed", &o->ransac_order_seed, 0, 2147483647);
  r.ReadEnum("initialization_matches", &o->initialization_matches);
  r.Read("max_reprojection_px", &o->max_reprojection_px, 0.01, 100.0);
  r.Read("min_triangulation_deg", &o->min_triangulation_deg, 0.0, 90.0);
  r.Read("max_depth_baselines", &o->max_depth_baselines, 1.0, 1e6);
  r.Read("pnp_min_inliers", &o->pnp_min_inliers, 4, 1000000);
  r.Read("pnp_reprojection_px", &o->pnp_reprojection_px, 0.01, 100.0);
  r.Read("pnp_iterations", &o->pnp_iterations, 1, 100000);
  r.Read("track_reference_keyframes", &o->track_reference_keyframes, 1, 100);
  r.Read("projection_radius_px", &o->projection_radius_px, 0.0, 1000.0);
  r.Read("projection_skips_icgm_rejected", &o->projection_skips_icgm_rejected);
  r.Read("projection_max_hamming", &o->projection_max_hamming, 0, 512);
  r.Read("keyframe_tracked_ratio", &o->keyframe_tracked_ratio, 0.0, 1.0);
  r.Read("keyframe_min_tracked", &o->keyframe_min_tracked, 0, 1000000);
  r.Read("keyframe_max_interval", &o->keyframe_max_interval, 1, 100000);
  r.Read("keyframe_min_feature_ratio", &o->keyframe_min_feature_ratio, 0.0, 1.0);
  r.Read("keyframe_min_baseline_depth_ratio", &o->keyframe_min_baseline_depth_ratio, 0.0, 1.0);
  r.Read("keyframe_force_tracked", &o->keyframe_force_tracked, 0, 1000000);
  r.Read("ba_window_keyframes", &o->ba_window_keyframes, 0, 1000);
  r.Read("ba_fixed_keyframes", &o->ba_fixed_keyframes, 1, 1000);
  r.Read("ba_covisible_fixed", &o->ba_covisible_fixed);
  r.Read("local_map_keyframes", &o->local_map_keyframes, 2, 1000);
  r.Read("lost_frames_before_reset", &o->lost_frames_before_reset, 1, 100000);
  r.Read("relocalize", &o->relocalize);
  r.Read("relocalize_keyframes", &o->relocalize_keyframes, 1, 1000);
  r.Read("relocalize_radius_px", &o->relocalize_radius_px, 0.0, 1000.0);
  r.Read("relocalize_pnp_iterations", &o->relocalize_pnp_iterations, 1, 100000);
  r.Read("relocalize_good_keyframe_points", &o->relocalize_good_keyframe_points, 0, 100000);
  r.Read("carry_scale_over_reset", &o->carry_scale_over_reset);
  r.Read("relocalize_while_initializing", &o->relocalize_while_initializing);
  r.Read("reset_bridge_max_s", &o->reset_bridge_max_s, 0.0, 1e6);
  r.Read("wheel_min_baseline_m", &o->wheel_min_baseline_m, 0.0, 100.0);
  r.Read("wheel_scale_gain", &o->wheel_scale_gain, 0.0, 1.0);
  r.Read("wheel_prediction", &o->wheel_prediction);
  r.Read("wheel_prior_threshold", &o->wheel_prior_threshold, 0.001, 1.0);
  r.Read("prior_from_prediction_error", &o->prior_from_prediction_error);
  r.Read("prior_threshold_per_px", &o->prior_threshold_per_px, 0.0, 1.0);
  r.Read("prior_threshold_min", &o->prior_threshold_min, 0.001, 1.0);
  r.Read("prior_threshold_max", &o->prior_threshold_max, 0.001, 1.0);
  r.Read("prior_tolerance_errors", &o->prior_tolerance_errors, 0.0, 100.0);
  r.Read("new_points_from_map_group", &o->new_points_from_map_group);
  r.Read("new_points_from_prior", &o->new_points_from_prior);
  r.Read("prior_from_pnp", &o->prior_from_pnp);
  r.Read("new_point_prior_radius_px", &o->new_point_prior_radius_px, 1.0, 10000.0);
  r.Read("new_point_icgm_baseline_keyframes", &o->new_point_icgm_baseline_keyframes, 0, 100);
  r.Read("track_icgm_baseline_frames", &o->track_icgm_baseline_frames, 0, 300);
  r.Read("track_icgm_baseline_rotation_prior", &o->track_icgm_baseline_rotation_prior);
  r.Read("track_icgm_baseline_max_translation_depth_ratio",
         &o->track_icgm_baseline_max_translation_depth_ratio, 0.0, 1.0);
  r.Read("new_point_min_baseline_depth_ratio", &o->new_point_min_baseline_depth_ratio, 0.0, 1.0);
  r.Read("new_point_extra_keyframes", &o->new_point_extra_keyframes, 0, 100);
  r.Read("new_point_extra_min_baseline_depth_ratio", &o->new_point_extra_min_baseline_depth_ratio,
         0.0, 1.0);
  r.Read("cull_outlier_frames", &o->cull_outlier_frames, 0, 1000);
  r.Read("new_point_confirm_px", &o->new_point_confirm_px, 0.0, 100.0);
  r.Read("new_point_contradiction_px", &o->new_point_contradiction_px, 0.0, 200.0);
  r.Read("moving_point_checks_with_wheels", &o->moving_point_checks_with_wheels);
  r.Read("dynamic_mask_radius_px", &o->dynamic_mask_radius_px, 0.0, 200.0);
  r.Read("dynamic_mask_min_votes", &o->dynamic_mask_min_votes, 1, 1000);
  r.Read("pnp_verified_min_keyframes", &o->pnp_verified_min_keyframes, 0, 1000);
  r.Read("pnp_verified_min_span_s", &o->pnp_verified_min_span_s, 0.0, 1000.0);
  r.Read("pnp_verified_min_points", &o->pnp_verified_min_points, 4, 1000000);
  r.Read("scene_depth_band", &o->scene_depth_band, 0.0, 1e6);
  r.Read("new_point_expected_parallax", &o->new_point_expected_parallax);
  r.Read("new_point_min_measured_deg", &o->new_point_min_measured_deg, 0.0, 90.0);
  if (o->scene_depth_band > 0.0 && o->scene_depth_band < 1.0) {
    throw LoadError(r.path() + ".scene_depth_band must be 0 (off) or at least 1");
  }
  r.Read("rotation_only_parallax_deg", &o->rotation_only_parallax_deg, 0.0, 90.0);
  r.Read("rotation_only_when_lost", &o->rotation_only_when_lost);
  r.Read("rotation_only_keeps_pnp_pose", &o->rotation_only_keeps_pnp_pose);
  if (o->prior_threshold_min > o->prior_threshold_max) {
    throw LoadError(r.path() + ".prior_threshold_min exceeds prior_threshold_max");
  }
}

MonoOptions::MonoOptions() {
  // Monocular bundle adjustment: reprojection only.
  bundle_adjustment.use_depth = false;
  bundle_adjustment.max_iterations = 10;
  // No wall-clock cap: the iterations decide, so a run gives the same result on a loaded
  // machine (a keyframe's adjustment takes ~0.1 s of CPU).
  bundle_adjustment.max_solver_time_s = 0.0;
  // Two-view reprojection: 2 dof, 99 %.
  bundle_adjustment.outlier_chi2 = 9.21;
  features.max_features = 1000;
  // ICGM against the map points' constant-velocity reprojection (mono_odometry.h). Thr 0.05:
  // a hand-held camera's prediction is rougher than the wheels' (0.02 lost matches on fr1/xyz).
  icgm.motion_prior = true;
  icgm.motion_prior_threshold = 0.05;
}

void ReadMonoOptions(const OptionReader& root, MonoOptions* options) {
  const OptionReader mono = root.Section("mono");
  const OptionReader features = root.Section("features");
  const OptionReader matcher = root.Section("matcher");
  const OptionReader icgm = root.Section("icgm");
  const OptionReader ba = root.Section("bundle_adjustment");
  const OptionReader wheel = root.Section("wheel_odometry");
  ReadOptions(mono, &options->vo);
  ReadOptions(features, &options->features);
  ReadOptions(matcher, &options->matcher);
  ReadOptions(icgm, &options->icgm);
  ReadOptions(ba, &options->bundle_adjustment);
  ReadOptions(wheel, &options->wheel_odometry);
  OptionReader::RejectUnknownKeys({&mono, &features, &matcher, &icgm, &ba, &wheel, &root});
}

MonoOptions LoadMonoOptions(const std::string& path) {
  MonoOptions options;
  ReadMonoOptions(OptionReader::FromFile(path), &options);
  return options;
}

}  // namespace icgm
