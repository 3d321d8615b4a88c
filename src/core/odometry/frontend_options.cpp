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
  reader.Read("keyframe_window", &options->keyframe_window, 0, 100000);
  reader.Read("revisit_max_translation_m", &options->revisit_max_translation_m, 1e-3, 100.0);
  reader.Read("revisit_max_rotation_deg", &options->revisit_max_rotation_deg, 1e-3, 180.0);
  reader.Read("revisit_attempts", &options->revisit_attempts, 0, 1000);
  reader.Read("keyframe_extra_references", &options->keyframe_extra_references, 0, 100);
  reader.Read("frame_extra_references", &options->frame_extra_references, 0, 100);
  reader.Read("reference_agreement_m", &options->reference_agreement_m, 0.0, 10.0);
  reader.Read("reference_agreement_deg", &options->reference_agreement_deg, 0.0, 180.0);
  reader.Read("weight_by_octave", &options->weight_by_octave);
  reader.Read("compensate_depth_timing", &options->compensate_depth_timing);
  reader.Read("depth_timing_min_s", &options->depth_timing_min_s, 0.0, 1.0);
  reader.Read("depth_timing_max_gap_s", &options->depth_timing_max_gap_s, 0.0, 10.0);
  reader.Read("depth_timing_averaged_velocity", &options->depth_timing_averaged_velocity);
  reader.Read("max_stamp_jump_s", &options->max_stamp_jump_s, 0.01, 1e9);
  reader.Read("velocity_prior", &options->velocity_prior);
  reader.Read("velocity_prior_steps", &options->velocity_prior_steps, 1, 1000);
  reader.Read("velocity_from_vision", &options->velocity_from_vision);
  reader.Read("velocity_prior_median", &options->velocity_prior_median);
  reader.Read("velocity_prior_from_rest", &options->velocity_prior_from_rest);
  reader.Read("velocity_prior_skip_origin", &options->velocity_prior_skip_origin);
  reader.Read("velocity_rebase_at_keyframe", &options->velocity_rebase_at_keyframe, 0.0, 1.0);
  reader.Read("velocity_rebase_by_covariance", &options->velocity_rebase_by_covariance);
  reader.Read("velocity_rebase_persistent_deg", &options->velocity_rebase_persistent_deg, 0.0,
              180.0);
  reader.Read("velocity_rebase_max_m_per_frame", &options->velocity_rebase_max_m_per_frame, 0.0,
              10.0);
  reader.Read("velocity_rebase_evidence_confirm", &options->velocity_rebase_evidence_confirm);
  reader.Read("velocity_rebase_evidence_overrides_limit",
              &options->velocity_rebase_evidence_overrides_limit);
  reader.Read("select_by_evidence", &options->select_by_evidence);
  reader.Read("evidence_from_previous_frame", &options->evidence_from_previous_frame);
  reader.Read("evidence_margin", &options->evidence_margin, 0.0, 1.0);
  reader.Read("evidence_rotation_margin", &options->evidence_rotation_margin, 0.0, 1.0);
  reader.Read("evidence_rotation_margin_frames", &options->evidence_rotation_margin_frames, 0,
              1000000);
  reader.Read("evidence_ransac_runs", &options->evidence_ransac_runs, 1, 16);
  reader.Read("evidence_normalized", &options->evidence_normalized);
  reader.Read("evidence_min_depth_m", &options->evidence_min_depth_m, 0.0, 100.0);
  reader.Read("evidence_spread_weight", &options->evidence_spread_weight, 0.0, 100.0);
  reader.Read("evidence_far_hypothesis_m", &options->evidence_far_hypothesis_m, 0.0, 100.0);
  reader.Read("evidence_depth_order_margin", &options->evidence_depth_order_margin, 0.0, 1.0);
  reader.Read("evidence_depth_order_min_gap_m", &options->evidence_depth_order_min_gap_m, 0.0,
              100.0);
  reader.Read("evidence_depth_order_min_inliers", &options->evidence_depth_order_min_inliers, 0,
              100000);
  reader.Read("evidence_prediction_gate_m", &options->evidence_prediction_gate_m, 0.0, 10.0);
  reader.Read("evidence_prediction_gate_min_inliers",
              &options->evidence_prediction_gate_min_inliers, 0, 100000);
  reader.Read("evidence_prediction_gate_frames", &options->evidence_prediction_gate_frames, 0,
              1000000);
  reader.Read("select_across_references", &options->select_across_references);
  reader.Read("motion_prior_sigma_m", &options->motion_prior_sigma_m, 0.0, 10.0);
  reader.Read("motion_prior_sigma_deg", &options->motion_prior_sigma_deg, 1e-3, 180.0);
  reader.Read("motion_prior_covariance_scale", &options->motion_prior_covariance_scale, 1e-3, 1e6);
  reader.Read("motion_prior_sigma_by_steps", &options->motion_prior_sigma_by_steps);
  reader.Read("motion_prior_sigma_by_steps_exponent",
              &options->motion_prior_sigma_by_steps_exponent, 0.0, 4.0);
  reader.Read("motion_prior_sigma_by_steps_min_inliers",
              &options->motion_prior_sigma_by_steps_min_inliers, 0, 100000);
  reader.Read("motion_prior_start_frames", &options->motion_prior_start_frames, 0, 1000000);
  reader.Read("motion_prior_release_frames", &options->motion_prior_release_frames, 0, 100000);
  reader.Read("motion_prior_release_sigma_scale", &options->motion_prior_release_sigma_scale, 0.0,
              1e6);
  reader.Read("motion_prior_release_persistence", &options->motion_prior_release_persistence, 0.0,
              1.0);
  reader.Read("motion_prior_release_registered_velocity",
              &options->motion_prior_release_registered_velocity);
  reader.Read("prior_gate_deg", &options->prior_gate_deg, 0.0, 180.0);
  reader.Read("prior_gate_m", &options->prior_gate_m, 0.0, 10.0);
  reader.Read("prior_gate_near_m", &options->prior_gate_near_m, 0.0, 100.0);
  reader.Read("prior_gate_near_keyframes", &options->prior_gate_near_keyframes);
  reader.Read("prior_gate_max_frames", &options->prior_gate_max_frames, 1, 100000);
  reader.Read("velocity_gate_max_speed_mps", &options->velocity_gate.max_speed_mps, 0.0, 100.0);
  reader.Read("velocity_gate_max_accel_mps2", &options->velocity_gate.max_accel_mps2, 0.0, 1000.0);
  reader.Read("velocity_gate_max_rejected", &options->velocity_gate_max_rejected, 1, 100000);
  reader.Read("prior_reset_disagreement_m", &options->prior_reset.disagreement_m, 0.0, 10.0);
  reader.Read("prior_reset_frames", &options->prior_reset.frames, 1, 100000);
  reader.Read("prior_reset_self_agreement_m", &options->prior_reset.self_agreement_m, 0.0, 10.0);
  reader.Read("prior_reset_max_speed_mps", &options->prior_reset.max_speed_mps, 0.0, 100.0);
  RegistrationAgreementOptions& agreement = options->registration_agreement;
  reader.Read("agreement_covariance_scale", &agreement.covariance_scale, 0.0, 1e6);
  reader.Read("agreement_spread_weight", &agreement.spread_weight, 0.0, 1e6);
  reader.Read("agreement_max_m", &agreement.max_m, 0.0, 10.0);
  reader.Read("agreement_max_deg", &agreement.max_deg, 0.0, 180.0);
  reader.Read("agreement_min_registrations", &agreement.min_registrations, 2, 100);
  reader.Read("agreement_velocity_only", &options->agreement_velocity_only);
  reader.Read("agreement_keyframe_max_postponed", &options->agreement_keyframe_max_postponed, 0,
              100000);
  reader.Read("dynamic_masking", &options->dynamic_masking);
  reader.Read("mask_growth_cells", &options->mask_growth_cells, 0, 64);
  reader.Read("reference_dynamic_votes", &options->reference_dynamic_votes, 1, 1000);
  reader.Read("static_inlier_refit", &options->static_inlier_refit);
  reader.Read("static_refit_fill_max_step_m", &options->static_refit_fill_max_step_m, 0.0, 10.0);
  reader.Read("refit_each_hypothesis", &options->refit_each_hypothesis);
  reader.Read("dense_refinement", &options->dense_refinement);
  ReadOptions(reader, &options->window);
  ResidualTrendOptions& trend = options->residual_trend;
  reader.Read("residual_trend_frames", &trend.frames, 0, 1000);
  reader.Read("residual_trend_min_drift_px", &trend.min_drift_px, 0.0, 1000.0);
  reader.Read("residual_trend_min_growth_px", &trend.min_growth_px, 0.0, 1000.0);
  reader.Read("residual_trend_noise_px", &trend.noise_px, 0.0, 1000.0);
  reader.Read("residual_trend_min_slope_sigmas", &trend.min_slope_sigmas, 0.0, 1000.0);
  reader.Read("residual_trend_max_residual_px", &trend.max_residual_px, 0.0, 10000.0);
  reader.Read("residual_trend_min_neighbours", &trend.min_neighbours, 0, 100000);
  reader.Read("residual_trend_neighbour_radius_px", &trend.neighbour_radius_px, 0.0, 10000.0);
  reader.Read("residual_trend_neighbour_max_angle_deg", &trend.neighbour_max_angle_deg, 0.0, 180.0);
  reader.Read("residual_trend_max_share", &trend.max_share, 0.0, 1.0);
  reader.Read("residual_trend_against_prediction", &trend.against_prediction);
  reader.Read("residual_trend_remove_median", &trend.remove_median);
  LocalMapOptions& map = options->local_map;
  reader.Read("local_map_keyframes", &map.keyframes, 0, 1000);
  reader.Read("local_map_search_px", &map.search_px, 0.5, 1000.0);
  reader.Read("local_map_max_descriptor_distance", &map.max_descriptor_distance, 0.0, 1e6);
  reader.Read("local_map_min_matches", &map.min_matches, 6, 100000);
  reader.Read("local_map_rounds", &map.rounds, 1, 100);
  reader.Read("local_map_iterations", &map.iterations, 1, 1000);
  reader.Read("local_map_huber_px", &map.huber_px, 0.01, 1000.0);
  reader.Read("local_map_max_correction_m", &map.max_correction_m, 0.0, 10.0);
  reader.Read("local_map_max_correction_deg", &map.max_correction_deg, 0.0, 180.0);
  reader.Read("local_map_fuse", &map.fuse);
  reader.Read("local_map_covariance_scale", &map.covariance_scale, 1e-3, 1e6);
  reader.Read("local_map_toward_prediction", &map.toward_prediction);
  reader.Read("local_map_toward_prediction_slack_m", &map.toward_prediction_slack_m, 0.0, 10.0);
  MapHypothesisOptions& located = options->map_hypothesis;
  reader.Read("map_hypothesis_keyframes", &located.keyframes, 0, 1000);
  reader.Read("map_hypothesis_max_descriptor_distance", &located.max_descriptor_distance, 0.0, 1e6);
  reader.Read("map_hypothesis_ratio", &located.ratio, 0.0, 1.0);
  reader.Read("map_hypothesis_same_point_m", &located.same_point_m, 0.0, 10.0);
  reader.Read("map_hypothesis_window_px", &located.window_px, 0.0, 10000.0);
  reader.Read("map_hypothesis_reprojection_px", &located.reprojection_px, 0.1, 1000.0);
  reader.Read("map_hypothesis_min_inliers", &located.min_inliers, 3, 100000);
  reader.Read("map_hypothesis_evidence_weight", &located.evidence_weight, 0.0, 100.0);
  reader.Read("map_hypothesis_persistence_keyframes", &located.persistence_keyframes, 0, 1000);
  reader.Read("map_hypothesis_persistence_span_s", &located.persistence_span_s, 0.0, 1000.0);
  reader.Read("map_hypothesis_persistence_radius_m", &located.persistence_radius_m, 0.001, 10.0);
  KeyframeBaOptions& ba = options->keyframe_ba;
  reader.Read("keyframe_ba_keyframes", &ba.keyframes, 0, 100);
  reader.Read("keyframe_ba_fixed_keyframes", &ba.fixed_keyframes, 1, 99);
  reader.Read("keyframe_ba_min_spacing_m", &ba.min_spacing_m, 0.0, 10.0);
  reader.Read("keyframe_ba_min_spacing_deg", &ba.min_spacing_deg, 0.0, 180.0);
  reader.Read("keyframe_ba_match_px", &ba.match_px, 0.5, 1000.0);
  reader.Read("keyframe_ba_max_descriptor_distance", &ba.max_descriptor_distance, 0.0, 1e6);
  reader.Read("keyframe_ba_min_points", &ba.min_points, 3, 100000);
  reader.Read("keyframe_ba_iterations", &ba.iterations, 1, 1000);
  reader.Read("keyframe_ba_huber_sigmas", &ba.huber_sigmas, 0.0, 100.0);
  reader.Read("keyframe_ba_depth_sigma_m", &ba.depth_sigma_m, 1e-6, 1.0);
  reader.Read("keyframe_ba_depth_sigma_per_m2", &ba.depth_sigma_per_m2, 0.0, 1.0);
  reader.Read("keyframe_ba_max_correction_m", &ba.max_correction_m, 0.0, 10.0);
  reader.Read("keyframe_ba_max_correction_deg", &ba.max_correction_deg, 0.0, 180.0);
  reader.Read("keyframe_ba_link_covariance_scale", &ba.link_covariance_scale, 0.0, 1e6);
  AnchorOptions& anchor = options->anchor;
  reader.Read("anchor_keyframes", &anchor.keyframes, 0, 100);
  reader.Read("anchor_keyframe_min_inliers", &anchor.keyframe_min_inliers, 0, 100000);
  reader.Read("anchor_min_inliers", &anchor.min_inliers, 3, 100000);
  reader.Read("anchor_gain", &anchor.gain, 0.0, 1.0);
  reader.Read("anchor_max_correction_m", &anchor.max_correction_m, 0.0, 10.0);
  reader.Read("anchor_max_correction_deg", &anchor.max_correction_deg, 0.0, 180.0);
  reader.Read("anchor_moves_chain", &anchor.moves_chain);
  reader.Read("anchor_hypothesis", &anchor.hypothesis);
}

void ReadFrontendOptions(const OptionReader& odometry_root, const OptionReader& icgm_root,
                         FrontendOptions* options) {
  const OptionReader frontend = odometry_root.Section("frontend");
  const OptionReader registration = odometry_root.Section("registration");
  const OptionReader fusion = odometry_root.Section("fusion");
  const OptionReader wheel = odometry_root.Section("wheel_odometry");
  const OptionReader consistency = odometry_root.Section("depth_consistency");
  const OptionReader dense = odometry_root.Section("dense_refinement");
  const OptionReader features = icgm_root.Section("features");
  const OptionReader matcher = icgm_root.Section("matcher");
  const OptionReader icgm = icgm_root.Section("icgm");
  // The odometry may override ICGM settings for its frame-to-keyframe baselines.
  const OptionReader icgm_override = odometry_root.Section("icgm");
  ReadOptions(frontend, options);
  ReadOptions(registration, &options->registration);
  ReadOptions(fusion, &options->fusion);
  ReadOptions(wheel, &options->wheel);
  ReadOptions(consistency, &options->depth_consistency);
  ReadOptions(dense, &options->dense);
  ReadOptions(features, &options->features);
  ReadOptions(matcher, &options->matcher);
  ReadOptions(icgm, &options->icgm);
  ReadOptions(icgm_override, &options->icgm);
  // A misspelt key is an error naming it; odometry.yaml holds only the sections above.
  OptionReader::RejectUnknownKeys({&frontend, &registration, &fusion, &wheel, &consistency, &dense,
                                   &features, &matcher, &icgm, &icgm_override, &odometry_root});
}

}  // namespace icgm
