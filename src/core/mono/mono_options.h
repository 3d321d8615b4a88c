// Options of the monocular visual odometry (mono_odometry.h), read from config/mono.yaml:
// a `mono:` section (initialization, tracking, keyframes, local map, scale) plus the
// `features:`, `matcher:`, `icgm:`, `bundle_adjustment:` and `wheel_odometry:` sections of the
// shared components. Defaults are the shipped config/mono.yaml (tested).
#pragma once

#include <string>

#include "core/common/enum_names.h"
#include "core/features/descriptor_matcher.h"
#include "core/features/feature_extractor.h"
#include "core/icgm/icgm_matcher.h"
#include "core/odometry/wheel_odometry_buffer.h"
#include "core/optimization/bundle_adjustment.h"

namespace icgm {

class OptionReader;

// Matches the two-view initialization takes (`initialization_matches`): "icgm", those ICGM keeps
// (all with use_icgm false); "all", every ratio-test match (the essential matrix's RANSAC alone
// rejects outliers); "all_after_reset", every ratio-test match only when initializing again
// after a reset (the first map as with "icgm").
enum class MonoInitMatches { kIcgm, kAll, kAllAfterReset };

template <>
struct EnumNames<MonoInitMatches> {
  static constexpr EnumName<MonoInitMatches> kNames[] = {
      {MonoInitMatches::kIcgm, "icgm"},
      {MonoInitMatches::kAll, "all"},
      {MonoInitMatches::kAllAfterReset, "all_after_reset"}};
};

struct MonoVoOptions {
  // false: the plain ratio-test matches go to the geometry (comparison baseline).
  bool use_icgm = true;
  // A frame with fewer keypoints cannot be tracked (blank, dark or blurred image).
  int min_features = 50;

  // --- initialization (two-view: essential matrix, 5-point in RANSAC, Nister 2004) ---
  int init_min_matches = 60;            // matches to the reference frame needed to try
  double init_min_parallax_deg = 1.0;   // median triangulation angle of the initial map
  int init_min_points = 50;             // triangulated points of the initial map
  int init_max_frames = 60;             // frames without success before the reference is replaced
  double essential_threshold_px = 1.0;  // RANSAC inlier distance to the epipolar line
  double essential_confidence = 0.999;
  // The matches handed to the essential matrix's and PnP's RANSAC in an order drawn from this
  // seed (ransac_order.h; 0: input order). OpenCV's RANSAC draws from a fixed seed, so this gives
  // repeats of a run without ICGM (icgm_mono_vo --ransac-seed).
  int ransac_order_seed = 0;
  // Which matches to the reference frame the initialization uses (MonoInitMatches above).
  MonoInitMatches initialization_matches = MonoInitMatches::kIcgm;

  // --- triangulation of map points ---
  double max_reprojection_px = 2.0;    // in every view that created the point
  double min_triangulation_deg = 0.5;  // angle between the two viewing rays
  double max_depth_baselines = 200.0;  // depth / baseline above this: too uncertain

  // --- tracking (PnP in RANSAC against the local map) ---
  int pnp_min_inliers = 25;
  double pnp_reprojection_px = 3.0;
  int pnp_iterations = 100;
  // Reference keyframes tried for matches (newest first): the last keyframe and its
  // predecessors in the window.
  int track_reference_keyframes = 1;
  // Local map points projected with the tracked pose are matched to keypoints within this
  // radius (0 disables) whose Hamming distance to the point's descriptor is at most
  // projection_max_hamming and below matcher.ratio times the second best.
  double projection_radius_px = 10.0;
  int projection_max_hamming = 64;
  // With ICGM: the projection search skips the map points whose match to a reference keyframe
  // ICGM rejected on this frame (and no kept match gave), so the local map does not bring back
  // what ICGM judged inconsistent. false: it may match them again (they are mostly static
  // points the motion prior rejected: fr1/xyz 0.0236 m with the option, 0.0189 m without).
  bool projection_skips_icgm_rejected = false;

  // --- keyframes and local map ---
  // A new keyframe when the map points tracked drop below this fraction of those the last
  // keyframe sees, or below keyframe_min_tracked, or keyframe_max_interval frames passed.
  double keyframe_tracked_ratio = 0.7;
  int keyframe_min_tracked = 80;
  int keyframe_max_interval = 20;
  // A frame with fewer features than this share of the newest keyframe's (a blurred view) never
  // becomes a keyframe (0: any frame may).
  double keyframe_min_feature_ratio = 0.5;
  // Parallax before a keyframe: a frame tracking fewer than keyframe_min_tracked points becomes
  // a keyframe only once the camera moved at least this fraction of the median depth of its
  // tracked points since the newest keyframe, unless it tracks fewer than
  // keyframe_force_tracked points (tracking about to fail) or keyframe_max_interval frames
  // passed (frames tracking more points keep the keyframe_tracked_ratio rule). A hand-held
  // camera in a crowd otherwise makes a keyframe every frame, each a few mm from the one
  // before: static points fail min_triangulation_deg, few new points are added and the local
  // map (local_map_keyframes keyframes, then spanning as many frames) shrinks until tracking
  // is lost. Acts where the moving-point checks do (moving_point_checks_with_wheels): a robot
  // on wheels moves on, and crowded.yaml lost more maps with it (0.02). Off: at 0.02 it lowers
  // the hand-held crowd's error with ICGM, but on the 90-frame crowd clip it lets walkers into
  // the map that the moving-point checks kept out. 0: off.
  double keyframe_min_baseline_depth_ratio = 0.0;
  int keyframe_force_tracked = 40;
  // Windowed bundle adjustment over the newest ba_window_keyframes keyframes; the oldest
  // ba_fixed_keyframes of them are held fixed (gauge and scale). 0 disables the adjustment.
  int ba_window_keyframes = 6;
  int ba_fixed_keyframes = 2;
  // Older keyframes of the local map that observe the window's points join the adjustment as
  // fixed cameras (their observations hold the points and the scale).
  bool ba_covisible_fixed = true;
  // Keyframes of the local map (at least the window): their points are tracked by projection
  // and relocalized against; a point lives as long as one of them observes it.
  int local_map_keyframes = 20;

  // --- tracking loss and re-initialization ---
  // Consecutive frames without a pose before the map is dropped and re-initialized.
  int lost_frames_before_reset = 10;
  // A frame the newest keyframes' robust matches cannot track is matched to the newest
  // relocalize_keyframes keyframes of the local map with all ratio-test matches before it
  // counts as lost (false: no second try).
  bool relocalize = true;
  int relocalize_keyframes = 6;
  // ... and the local map projected with the constant-velocity prediction, matched within this
  // radius (0: off).
  double relocalize_radius_px = 25.0;
  int relocalize_pnp_iterations = 300;  // PnP RANSAC iterations of that second try
  // A frame that neither tracking nor that second try places is matched to the last good
  // keyframe, the newest that carried at least this many map points (0: off), by ICGM (its
  // consistent set between the two frames; every ratio-test match without ICGM) and placed by
  // PnP RANSAC on the kept matches to that keyframe's map points. In a crowd the newest
  // keyframes were made while walkers hid the room and carry few points; the last good one
  // still shows the room.
  int relocalize_good_keyframe_points = 0;
  // The new map's scale is taken from the speed before the loss (otherwise unit baseline).
  bool carry_scale_over_reset = true;
  // A reset keeps the lost map until a new one is initialized: every frame of the
  // re-initialization is first relocalized against it (as a lost frame is) and, when that
  // succeeds, tracking resumes in it with its scale and frame (a walker that hid the whole
  // view has passed). false: the map is dropped at the reset.
  bool relocalize_while_initializing = false;
  // The new map's reference frame is placed where the last map's constant velocity (its last
  // two tracked poses, in its units) carries the last tracked pose by the reference frame's
  // stamp, for at most this long after that pose (0: off, the reference frame takes the last
  // tracked pose). The camera keeps moving through the frames without a pose; the new map
  // then continues from about where it is instead of from where the last map lost it.
  double reset_bridge_max_s = 0.0;

  // --- metric scale from wheel odometry (when wheel samples and the extrinsic are given) ---
  // Wheel translation over the initial baseline below this: scale stays unknown.
  double wheel_min_baseline_m = 0.05;
  // At each keyframe, the map is rescaled toward the wheel scale over the window by this
  // fraction (0: scale fixed at initialization, 1: full correction at once).
  double wheel_scale_gain = 0.5;
  // With the metric scale, the pose prediction (ICGM motion prior, PnP seed, relocalization)
  // is the last pose moved by the wheels' motion since it (false: constant velocity).
  bool wheel_prediction = true;
  // ICGM motion prior Thr with that wheel prediction (icgm.motion_prior_threshold applies to
  // the constant-velocity one, which is off by more on a hand-held camera). At 0.01 ICGM kept
  // 35-50 of 300-400 matches a frame on crowded.yaml seed 5, dropping mostly static ones, and
  // ten seeds gave 6.70% of the distance against 5.21% at 0.02 (4.81% at 0.03).
  double wheel_prior_threshold = 0.02;

  // --- ICGM motion prior without wheels: Thr from the prediction's own error ---
  // The constant-velocity prediction of a hand-held camera is good while the hand moves
  // steadily and off by tens of pixels when it jerks. With prior_from_prediction_error the
  // prior's Thr and tolerance follow the error the prediction made on the last tracked frames
  // (median pixel distance between the tracked map points projected with the prediction and
  // where they were seen): Thr = prior_threshold_per_px * error, clamped to
  // [prior_threshold_min, prior_threshold_max]; tolerance = prior_tolerance_errors * error,
  // at least icgm.motion_prior_tolerance_px. false: icgm.motion_prior_threshold always.
  bool prior_from_prediction_error = false;
  double prior_threshold_per_px = 0.01;
  double prior_threshold_min = 0.02;
  double prior_threshold_max = 0.08;
  double prior_tolerance_errors = 3.0;

  // --- new map points (keyframes) with ICGM ---
  // true: a keyframe triangulates new points only from the matches to the previous keyframe
  // that fall in the ICGM group grown from the tracked map: seed pairs are drawn among the
  // matches whose map point is a PnP inlier of this frame (static by the map's own evidence),
  // and the group holding most of them wins. Walkers filling the view then cannot add their
  // points to the map as the largest consistent group can. false: the matches plain ICGM kept.
  bool new_points_from_map_group = false;
  // true: a keyframe triangulates new points only from the matches to the previous keyframe
  // that ICGM keeps with the motion prior of the tracked pose (PnP): every match gets the
  // position its keyframe keypoint would have in this frame if static, from its map point or,
  // without one, at the median depth of the keyframe's map points within
  // new_point_prior_radius_px of it (all of them when fewer than 3). The matches without a map
  // point then join the group anchored by the static map, as the tracking matches do, instead
  // of the largest group among themselves (a walker near a hand-held camera). Ignored with
  // new_points_from_map_group. false: the matches plain ICGM kept.
  bool new_points_from_prior = false;
  // true: without a wheel prediction, the motion prior's prediction of the tracking matches is
  // a first PnP pose (RANSAC on all ratio-test matches to the map, seeded with the
  // constant-velocity prediction) instead of the constant-velocity prediction, which a
  // hand-held camera's jitter puts off by more than Thr (ICGM then drops static matches).
  bool prior_from_pnp = false;
  double new_point_prior_radius_px = 60.0;
  // Long-baseline ICGM for new points: a keyframe's match to the previous keyframe gives a new
  // point only if its keypoint in this frame, matched (ratio test) from the keyframe this many
  // keyframes before the previous one, falls in the ICGM group (Thr icgm.threshold) grown from
  // the static map between those two views: seed pairs are drawn among the matches whose map
  // point this frame tracked as a PnP inlier, and the group holding most of them wins. Between
  // two consecutive views a slow walker stays within Thr of the room; over the longer baseline
  // its own motion puts it out. Keypoints the older keyframe does not match stay candidates.
  // Only with use_icgm, and where the moving-point checks act (moving_point_checks_with_wheels).
  // 0: off (the matches to the previous keyframe ICGM kept).
  int new_point_icgm_baseline_keyframes = 0;
  // Long-baseline ICGM for tracking: the frame is also matched (ratio test) with the frame this
  // many frames before it (the oldest one kept when tracking missed some, at least half as far
  // back), and ICGM (plain, Thr icgm.threshold) runs on those matches. Over a baseline of a few
  // tenths of a second a walker moves against the room by far more than Thr, while between the
  // frame and the newest keyframe (one to three frames) it stays consistent with it. The frame's
  // keypoints that this match puts outside the largest consistent group are not given to PnP
  // and the projection search skips them (keypoints it does not match stay usable). Only with
  // use_icgm, and where the moving-point checks act (moving_point_checks_with_wheels). 0: off.
  int track_icgm_baseline_frames = 0;
  // ... ICGM there with the motion prior of the rotation alone between the older frame's tracked
  // pose and this frame's prediction (each keypoint of the older frame turned into this one, no
  // depth needed: the hand's translation over the baseline is small against the walkers'
  // motion); Thr and tolerance as the tracking prior's. False, or no pose for either: plain ICGM.
  bool track_icgm_baseline_rotation_prior = false;
  // ... only while the camera's translation between the older frame's tracked pose and this
  // frame's prediction is below this fraction of the median depth of the frame's map-point
  // correspondences (at the prediction): over a longer baseline with parallax the room's own
  // points leave the group. Without either pose or a depth the check runs. 0: no bound.
  double track_icgm_baseline_max_translation_depth_ratio = 0.0;
  // Parallax of new points: a keyframe triangulates its new points with the previous keyframe
  // only if the camera moved at least this fraction of the median depth of its tracked points
  // since it; otherwise with the newest keyframe of the local map that far away (the farthest
  // one when none is), matched (ICGM with the tracked pose as motion prior) for the purpose. A
  // hand-held camera in a crowd makes a keyframe every frame or two, where a static point has
  // almost no parallax and fails min_triangulation_deg while a walker's own motion gives its
  // match plenty: the map then fills with walkers and starves until tracking is lost. The
  // views between the two keyframes confirm the points (new_point_confirm_px). Acts where the
  // moving-point checks do (moving_point_checks_with_wheels). 0: always the previous keyframe.
  double new_point_min_baseline_depth_ratio = 0.0;
  // More new points: after the first reference keyframe, the keyframe also triangulates its
  // ICGM matches (tracked pose as motion prior) with up to this many older keyframes of the
  // local map (newest first) that lie at least new_point_extra_min_baseline_depth_ratio times
  // the tracked points' median depth away, each matched for the purpose. Keypoints that got a
  // point from an earlier reference are skipped; the views between confirm the points
  // (new_point_confirm_px). With a keyframe every frame or two, the previous keyframe is too
  // close for most static points to pass min_triangulation_deg. 0: off.
  int new_point_extra_keyframes = 0;
  double new_point_extra_min_baseline_depth_ratio = 0.01;

  // --- map points that move (walkers): consistency over several frames ---
  // A map point matched in this many tracked frames in a row without being an inlier of the
  // tracked pose (reprojection above pnp_reprojection_px) is deleted from the map: a static
  // point keeps reprojecting where it is seen, a point on a walker drifts away from its
  // triangulated position. 0: points are never deleted for that.
  int cull_outlier_frames = 2;
  // A keyframe's new point (triangulated from the previous keyframe and this frame) must also
  // be seen in an earlier view that did not make it: the frame tracked just before this one
  // (when it is not the previous keyframe) or the keyframe before the previous one. Seen = a
  // keypoint within this radius (px) of the point's projection there whose descriptor is at
  // most projection_max_hamming from this frame's. A walker's point is elsewhere in those
  // views (with a small baseline its own motion is what gives it parallax), a static point is
  // where it projects. Points in front of no such view are added. 0: off.
  double new_point_confirm_px = 3.0;
  // With new_point_confirm_px: a view rejects the point only when it contradicts it, not when it
  // merely fails to show it. The view's keypoint most like the point's descriptor (at most
  // projection_max_hamming) within this radius (px) of the projection is taken: within
  // new_point_confirm_px it confirms the point, farther it shows the point elsewhere (moving),
  // and none is no evidence (a static corner missed by the detector in that view keeps its
  // point). 0: off (every view that sees the point in front must show it within
  // new_point_confirm_px). At 10 the hand-held crowd keeps its map more often but more new
  // points lie on walkers, and Bonn with ICGM gets worse (8.11% against 7.56%).
  double new_point_contradiction_px = 0.0;
  // false: cull_outlier_frames and new_point_confirm_px act only on inputs without wheel
  // odometry (a hand-held camera). With the wheels' prediction and motion prior few walker
  // points reach the map, and the two checks then mostly remove static points.
  bool moving_point_checks_with_wheels = false;
  // Moving regions: the pixels of this frame's matches to map points that ICGM (its motion
  // prior) rejected or that are outliers of the tracked pose, with those of the frame before,
  // mark where something moves. A keyframe's new point within dynamic_mask_radius_px of at
  // least dynamic_mask_min_votes of them is not added. Acts where the two checks above do
  // (moving_point_checks_with_wheels). 0: off.
  double dynamic_mask_radius_px = 0.0;
  int dynamic_mask_min_votes = 2;

  // --- map points that persist (the room stays, people move within seconds) ---
  // A map point is verified once keyframes saw it in place (created there, or tracked as an
  // inlier of the keyframe's pose, an observation the bundle adjustment kept) at least
  // pnp_verified_min_keyframes times over at least pnp_verified_min_span_s seconds. A point on
  // a walker rarely stays in place that long (hand-held crowd: 1-6% of the verified
  // correspondences lie on walkers, against 9-33% of all). Tracking then also runs PnP RANSAC
  // on the verified correspondences alone when there are at least pnp_verified_min_points of
  // them, refines that pose on its inliers among all, and takes it instead of the pose from
  // all correspondences when it fits more of the verified points (a walker near the camera
  // pulled the other). Acts where the moving-point checks do (moving_point_checks_with_wheels).
  // Off: it changes few frames and did not lower the error (hand-held crowd 12.84% against
  // 11.56%, Bonn 7.32% against 7.56%, fr1/xyz 0.0190 m). 0: off.
  int pnp_verified_min_keyframes = 0;
  double pnp_verified_min_span_s = 0.5;
  int pnp_verified_min_points = 30;

  // --- scale inside a map (without wheels) ---
  // Scene-depth hold: the median depth (map units) of the points the map's second
  // initialization keyframe sees is the map's reference depth. At each keyframe, after the
  // bundle adjustment, the median depth of the points the keyframe tracks is compared with it;
  // outside [reference / band, reference x band] the local map (keyframes, points, the poses
  // of the constant-velocity prediction) is scaled about the newest keyframe so that the depth
  // lies on the band's edge. The poses already given out stay where they are; the motion after
  // the keyframe is measured in the held units. A hand-held camera in a room sees depths that
  // change within a small factor, while a map made of short-baseline keyframes can shrink or
  // grow by orders of magnitude (points whose noise enlarged their parallax pass
  // min_triangulation_deg and lie too close). Not with a metric (wheel) scale. 0: off; else
  // at least 1.
  double scene_depth_band = 0.0;
  // Parallax of new points without the noise's selection: a keyframe's candidate point is
  // accepted when the angle its two rays would make at the depth of this frame's tracked points
  // (their median, map units) reaches min_triangulation_deg, and its measured angle reaches
  // new_point_min_measured_deg (max_depth_baselines, another cut on the measured depth, is not
  // applied). Gating on the measured angle keeps the points
  // whose pixel noise enlarged a small parallax; their depths come out short, and a camera
  // walking along its view (most points near the focus of expansion) sees its map shrink
  // keyframe by keyframe: on the walk through the crowd the scale by depth grows up to 59-fold
  // within a map. Inputs without wheels only. Off: over ten walk seeds it lowers the segment
  // error in both modes alike (-14 / -17 points), so ICGM does not separate; fr1/xyz 0.0183 m.
  // false: the measured angle decides.
  bool new_point_expected_parallax = false;
  double new_point_min_measured_deg = 0.0;

  // --- low parallax (without wheels) ---
  // Rotation-only tracking: a tracked frame whose matches to the newest keyframe (those given to
  // the geometry: ICGM's consistent set; every ratio-test match without ICGM) a rotation about
  // the camera centre explains with a median parallax below this (deg, rotation_only.h) is a
  // low-parallax view: its orientation is the newest keyframe's turned by that rotation and its
  // position is held at the newest keyframe's (PnP's translation is noise there). It does not
  // become a keyframe (no triangulation at low parallax) unless fewer than
  // keyframe_force_tracked points are tracked, when the PnP pose stands. Full PnP and keyframes
  // resume once the parallax to the newest keyframe reaches it. 0: off.
  double rotation_only_parallax_deg = 0.0;
  // With it: a frame that neither tracking nor relocalization places, but whose matches to the
  // newest keyframe a rotation explains below that parallax, is posed so (the newest keyframe's
  // position) and does not count as lost: the map is kept.
  bool rotation_only_when_lost = false;
  // A low-parallax view keeps its PnP pose; only the keyframe waits for parallax (measured on
  // the matches given to the geometry).
  bool rotation_only_keeps_pnp_pose = false;
};

// Fills `options` from a `mono:` section; throws LoadError on bad values.
void ReadOptions(const OptionReader& reader, MonoVoOptions* options);

struct MonoOptions {
  MonoOptions();
  MonoVoOptions vo;
  FeatureOptions features;
  MatcherOptions matcher;
  IcgmOptions icgm;
  BundleAdjustmentOptions bundle_adjustment;
  WheelOdometryOptions wheel_odometry;
};

// Reads every section of a mono.yaml root; unknown sections or keys throw LoadError naming them.
void ReadMonoOptions(const OptionReader& root, MonoOptions* options);
// Loads a file (e.g. config/mono.yaml); throws LoadError.
MonoOptions LoadMonoOptions(const std::string& path);

}  // namespace icgm
