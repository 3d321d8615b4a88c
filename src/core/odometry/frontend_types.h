// Options and per-frame outputs of the RGB-D front end (rgbd_frontend.h).
#pragma once

#include <cmath>
#include <cstddef>
#include <memory>
#include <optional>
#include <vector>

#include <Eigen/Core>
#include <opencv2/core.hpp>

#include "core/common/pose.h"
#include "core/common/status.h"
#include "core/common/time.h"
#include "core/features/descriptor_matcher.h"
#include "core/features/feature_extractor.h"
#include "core/icgm/icgm_matcher.h"
#include "core/odometry/keyframe_bundle_adjustment.h"
#include "core/odometry/local_map.h"
#include "core/odometry/anchor_keyframes.h"
#include "core/odometry/hypothesis_evidence.h"
#include "core/odometry/map_hypothesis.h"
#include "core/odometry/odometry_fusion.h"
#include "core/odometry/pose_window.h"
#include "core/odometry/prior_reset.h"
#include "core/odometry/registration_agreement.h"
#include "core/odometry/residual_trend.h"
#include "core/odometry/velocity_history.h"
#include "core/odometry/wheel_odometry_buffer.h"
#include "core/registration/dense_refinement.h"
#include "core/registration/depth_consistency.h"
#include "core/registration/rgbd_registration.h"

namespace icgm {

class OptionReader;

struct FrontendOptions {
  // false: register with the plain ratio-test matches (baseline without ICGM).
  bool use_icgm = true;
  // Keyframe policy. Each frame is registered to the last keyframe (interval phi of the thesis,
  // R_x from M_x and M_(x-phi), with phi chosen adaptively); the current frame becomes the new
  // keyframe when the registration weakens or the motion since the keyframe grows:
  int max_keyframe_interval_phi = 30;      // frames since the keyframe
  int keyframe_min_inliers = 120;          // inliers to the keyframe below this
  double keyframe_min_inlier_ratio = 0.0;  // inlier ratio below this (0 disables)
  double keyframe_max_translation_m = 0.25;
  double keyframe_max_rotation_deg = 15.0;
  // When registration to the keyframe fails, try the previous frame before falling back.
  bool retry_previous_frame = true;
  // Local map: recent keyframes kept as candidate references (0 or 1: plain chain).
  int keyframe_window = 30;
  // A window keyframe is a candidate when the current pose is this close to it...
  double revisit_max_translation_m = 0.15;
  double revisit_max_rotation_deg = 10.0;
  // ...and at most this many nearest candidates are tried per new-keyframe decision.
  int revisit_attempts = 2;
  // A new keyframe's pose also uses its registrations to up to this many other nearby window
  // keyframes (information-weighted mean), averaging the noise of single links.
  int keyframe_extra_references = 4;
  // The same for every other frame (costs one registration per extra reference).
  int frame_extra_references = 1;
  // An extra (or revisited) keyframe's estimate of the frame is used only when it lies within
  // these bounds of the reference's estimate: a keyframe whose own pose went wrong (placed while
  // walkers filled the view), or a registration that followed a walker, would otherwise pull the
  // mean by its full error, since the registration covariances know nothing of keyframe pose
  // errors. 0: no bound on that component.
  double reference_agreement_m = 0.0;
  double reference_agreement_deg = 0.0;
  // - select_across_references (with select_by_evidence): the hypotheses of the frame's
  //   registrations to its reference and to the nearby keyframes are pooled and judged by the
  //   evidence summed over all those references and the previous frame (walkers stand
  //   elsewhere in each; the static scene persists), then averaged with the agreeing links.
  bool select_across_references = false;
  // Weight reprojection residuals by the keypoint's pyramid scale (ORB octaves).
  bool weight_by_octave = true;
  // Depth captured at another instant than the colour image (depth stamp, plus the camera's
  // depth_time_offset_s, differs from the colour stamp): re-render the depth image at the colour
  // instant with the camera velocity of the previous two frames (depth_warp.h), so keypoints
  // are lifted with the depth of their own instant.
  bool compensate_depth_timing = true;
  double depth_timing_min_s = 0.001;      // smaller time differences are ignored
  // The camera velocity (for the depth timing and a rolling shutter, camera.h readout_s) needs
  // two frames at most this apart.
  double depth_timing_max_gap_s = 0.1;
  // With velocity_prior_steps > 1: that velocity is the velocity history's (the last
  // velocity_prior_steps steps, velocity_history.h) instead of the last step's, and a keyframe
  // is not carried again with its own step. Among walkers a single step errs by 1-3 cm (0.3-0.9
  // m/s at 30 Hz), more than the hand moves the camera, so the last step's velocity skews the
  // rows of a rolling shutter by more than the shutter itself does.
  bool depth_timing_averaged_velocity = false;

  // A frame stamped more than this after the previous one is ignored until the next frame
  // follows it within the same bound (then both are believed: a real gap, not a wrong stamp).
  double max_stamp_jump_s = 5.0;
  // Crowds without wheels (a hand-held camera among walkers; off by default, on in
  // config/odometry_handheld_crowd.yaml), each measured against the plain pipeline in README:
  // - velocity_prior: when no wheel odometry covers the span, the constant-velocity prediction
  //   of the last steps serves where the wheels' would (ICGM's motion prior when
  //   icgm.motion_prior is on, the prediction's hypothesis, the carried dynamic mask).
  bool velocity_prior = false;
  // The constant-velocity prediction (velocity_prior) spans this many past steps (1: the last
  // step only): single steps err by centimetres where the camera moves millimetres per frame.
  int velocity_prior_steps = 1;
  // The velocity history (velocity_prior_steps > 1) follows the frames' poses as registered
  // (reference keyframe pose times the registration), before the motion prior fuses them with
  // the prediction: otherwise the prior feeds its own output back and keeps a wrong early
  // velocity for as long as the history spans.
  bool velocity_from_vision = false;
  // The velocity over those steps is the per-component median of the single steps' twists
  // instead of the mean motion from the oldest to the newest pose (velocity_history.h).
  bool velocity_prior_median = false;
  // Until velocity_prior_steps steps are held (start, or after a gap), the missing steps count
  // as standing still: the velocity is scaled by steps held / velocity_prior_steps, so the
  // first, single registration step (which errs by a centimetre among walkers) does not set
  // the prediction for the next frames alone.
  bool velocity_prior_from_rest = false;
  // The run's first keyframe frame (its origin, registered to nothing) stays out of the velocity
  // history. Every registration to the first keyframe shares much of one offset (a pan mistaken
  // for a slide: Bonn crowd frames 1-7, about 7 mm left and 7 mm up), which cancels between
  // those frames' poses but enters a velocity measured from the exact origin.
  bool velocity_prior_skip_origin = false;
  // With velocity_from_vision: when a frame becomes a keyframe, later frames are registered to
  // its fused pose, not to the pose its registration measured; the velocity history is then
  // re-expressed by this share of the offset between the two (1: its newest pose becomes the
  // fused one; 0: off). Without it the offset enters the history as motion and the prediction
  // keeps the drift it caused; with all of it the velocity follows the registrations alone.
  double velocity_rebase_at_keyframe = 0.0;
  // The rebase share scaled by how much the registration outweighs the prior (translation and
  // rotation apart): sigma^2 / (sigma^2 + variance), sigma the motion prior's per-frame sigma,
  // variance the registration covariance's mean diagonal (as claimed, before the motion prior's
  // scale). A registration that claims less than the prior rebases the history the most.
  bool velocity_rebase_by_covariance = false;
  // > 0: the history is rebased only when the offset's translation turns less than this from the
  // previous keyframe's offset (a drift that keeps one direction, not registration noise, which
  // changes direction from one keyframe to the next). 0: at every keyframe.
  double velocity_rebase_persistent_deg = 0.0;
  // > 0: rebased only when the offset, divided by the frames since the reference keyframe, stays
  // under this: a slow drift of the prediction away from good registrations, not a registration
  // pulling centimetres away from the prediction every frame. 0: no limit.
  double velocity_rebase_max_m_per_frame = 0.0;
  // The whole frame's evidence (depth and edge agreement against the reference and the previous
  // frame, as select_by_evidence counts it) at the keyframe's registered and at its fused pose:
  // - confirm: a rebase the options above allow happens only where the registered pose explains
  //   more of the frame than the fused one (the registration, not the prediction, is right);
  // - overrides_limit: a keyframe velocity_rebase_max_m_per_frame turns away is still rebased
  //   where the registered pose explains more of the frame.
  bool velocity_rebase_evidence_confirm = false;
  bool velocity_rebase_evidence_overrides_limit = false;
  // - select_by_evidence: several motion hypotheses per frame pair (ICGM + RANSAC; RANSAC on the
  //   matches it left out; RANSAC on the matches that agree with the predicted motion), the
  //   winner chosen by the whole frame's depth and edge agreement (depth_consistency.h), so
  //   the set a walker filling the view forms cannot win by its number of matches.
  bool select_by_evidence = false;
  // The previous frame judges the hypotheses too (its evidence added to the reference's):
  // walkers stand elsewhere in it than in the reference, the static scene persists.
  bool evidence_from_previous_frame = false;
  // Among the hypotheses within this share of the best one's evidence, the one nearest the
  // predicted motion wins (0: the evidence alone decides).
  double evidence_margin = 0.0;
  // Among the hypotheses within this share of the best one's evidence, the one with the smallest
  // rotation wins, in the first evidence_rotation_margin_frames frames (0: every frame); applied
  // after evidence_margin (0: off).
  double evidence_rotation_margin = 0.0;
  int evidence_rotation_margin_frames = 0;
  // The matches ICGM kept registered this many times, with RANSAC seeds registration.rng_seed
  // + 0, 1, ...; every further consistent set found (other inliers than the first run's) joins
  // the hypotheses, so one run's draws no longer decide which set the evidence sees (1: one run).
  int evidence_ransac_runs = 1;
  // Each evidence cue (depth, edges) divided by its largest count among the hypotheses before
  // they are summed (hypothesis_evidence.h), instead of the raw counts, where the depth count
  // outweighs the edges tenfold while hardly telling motions apart on far walls.
  bool evidence_normalized = false;
  // Only pixels at least this far in both frames count as evidence (0: the depth_consistency
  // range): where walkers pass nearer than the room, a motion that follows them can explain
  // their own pixels but not the room behind them.
  double evidence_min_depth_m = 0.0;
  // > 0: each hypothesis's inlier spread (cells of an 8 x 6 image grid holding one of its
  // inliers, over the most any hypothesis holds) joins the evidence at this weight. A walker's
  // consistent set lies on one compact silhouette, the room's around it; where a walker fills
  // much of the view its set explains as many depth and edge pixels as the room's (hypothesis
  // records, simulated hand-held crowd).
  double evidence_spread_weight = 0.0;
  // > 0: the ICGM-kept matches whose reference depth is at least this far form one more
  // hypothesis (registered on their own). Where a walker holds most of the matches, RANSAC's
  // consensus and every set formed from it follow the walker, and the room's points drop out as
  // the pose follows it (hypothesis records, simulated hand-held crowd); the room lies beyond
  // the walkers.
  double evidence_far_hypothesis_m = 0.0;
  // > 0: depth order (hypothesis_evidence.h ChooseByDepthOrder). Among the hypotheses within
  // this share of the best evidence score holding at least evidence_depth_order_min_inliers
  // inliers, the one whose inliers' median reference depth lies farthest wins, when at least
  // evidence_depth_order_min_gap_m beyond the chosen one's. Walkers stand in front of the room:
  // where one fills the view, the set it forms explains the frame's depth and edges as well as
  // the room's set (hypothesis records, simulated hand-held crowd), but lies nearer.
  double evidence_depth_order_margin = 0.0;
  double evidence_depth_order_min_gap_m = 0.3;
  int evidence_depth_order_min_inliers = 20;
  // > 0: prediction gate (hypothesis_evidence.h ChooseWithinPredictionGate). A hand moves the
  // camera a few millimetres per frame; where the winner of the evidence choice puts the frame
  // more than this far from the constant-velocity prediction and another hypothesis with at
  // least evidence_prediction_gate_min_inliers inliers lies within it, the best-scored of those
  // wins instead. Where walkers walking away fill the view, the set they form explains their
  // near depth and edges best and moves the camera 2-3 cm back per frame (hypothesis records,
  // Bonn crowd frames 15-28), while the room's set stays within a centimetre of the prediction.
  // Only in the first evidence_prediction_gate_frames frames (0: every frame); no prediction
  // (first frame, after a gap): no gate.
  double evidence_prediction_gate_m = 0.0;
  int evidence_prediction_gate_min_inliers = 50;
  int evidence_prediction_gate_frames = 0;
  // - motion prior (with velocity_prior, without wheels): the frame's vision estimate is fused
  //   with the constant-velocity prediction, the prediction weighted as a step deviating from
  //   constant velocity by motion_prior_sigma_m / _deg per frame (a hand-held camera's inertia),
  //   the estimate by its registration covariance times motion_prior_covariance_scale (the
  //   covariance claims too little where walkers and far walls leave a pan and a sideways
  //   slide nearly alike). 0 disables.
  double motion_prior_sigma_m = 0.0;
  double motion_prior_sigma_deg = 0.5;
  double motion_prior_covariance_scale = 1.0;
  // While the velocity history (velocity_prior_steps > 1) holds fewer steps than it spans
  // (start, or after a gap), the prior's sigmas are scaled by velocity_prior_steps / steps held:
  // the velocity from the oldest to the newest pose errs by the poses' error over the span, so a
  // prediction from one registered step is about velocity_prior_steps times less certain than
  // one from a full history.
  bool motion_prior_sigma_by_steps = false;
  // The scale is (velocity_prior_steps / steps held) to this power (1: linear, 0.5: its square
  // root, a milder widening).
  double motion_prior_sigma_by_steps_exponent = 1.0;
  // Widened only on frames whose registration has at least this many inliers (0: every frame):
  // a frame with few inliers, e.g. one a walker fills, keeps the full prior.
  int motion_prior_sigma_by_steps_min_inliers = 0;
  // > 0: frames before this index that are registered to the run's first keyframe keep their
  // registered pose (no fusion with the prediction). The first keyframe is the run's origin, so
  // those registrations' errors do not add up, while the prediction's do: its velocity starts
  // from the first registered step alone (Bonn crowd: 9.5 mm where the hand moved 1.6 mm), and
  // the fused pose, which follows the prediction within a millimetre, carries that error on.
  int motion_prior_start_frames = 0;
  // - motion prior release (0 frames: off): after motion_prior_release_frames frames in a row
  //   each registered to the frame just before it (that frame became a keyframe, or the
  //   keyframe failed and the previous frame was used), registration and prediction are no
  //   longer independent: the reference's pose is the previous fused pose, the velocity history
  //   follows the fused poses, and the prior keeps an early registration's error step after
  //   step. While that lasts the prior's sigmas are scaled by motion_prior_release_sigma_scale
  //   (0: the registered step is taken as it is).
  //   With motion_prior_release_persistence > 0 the release also needs the registered steps to
  //   leave the prediction in one direction over those frames: the norm of the sum of their
  //   translation offsets from the predicted steps at least this share of the sum of the norms
  //   (an error the prior keeps, not registration noise around a right prediction).
  int motion_prior_release_frames = 0;
  double motion_prior_release_sigma_scale = 0.0;
  double motion_prior_release_persistence = 0.0;
  //   motion_prior_release_registered_velocity: while the frame is registered to the previous
  //   frame, after motion_prior_release_frames such frames in a row, the prediction takes its
  //   velocity from the registered steps chained on their own (no fused pose in between)
  //   instead of the velocity history.
  bool motion_prior_release_registered_velocity = false;
  // - prior gate (with velocity_prior, without wheels; 0: off): a vision step whose rotation
  //   differs from the constant-velocity prediction by more than prior_gate_deg (or whose
  //   translation differs by more than prior_gate_m, when > 0) gives way to the prediction: a
  //   walker filling the view won the registration (it turns the camera by degrees in one
  //   frame where the hand turns it by tenths). The frame then takes the predicted step, its
  //   dynamic regions come from that step's depth residuals (so the walker is marked, not the
  //   room), it makes no keyframe and adds no measured step to the velocity. At most
  //   prior_gate_max_frames frames in a row give way; the next one is taken as registered, so
  //   a wrong prediction cannot hold the estimate for long.
  double prior_gate_deg = 0.0;
  double prior_gate_m = 0.0;
  // - near-set gate (0: off; with the prior gate's limit prior_gate_max_frames): a registration
  //   whose chosen consistent set lies nearer than prior_gate_near_m (median reference depth of
  //   its inliers, select_by_evidence) was most likely made on a walker standing in front of
  //   the room, and gives way to the prediction like a prior-gated step: no keyframe, no
  //   measured step in the velocity. A keyframe made on such a set keeps the walker's motion in
  //   its pose, and the velocity history then carries it into the later frames' prediction.
  //   With prior_gate_near_keyframes such a frame may still become a keyframe, at the
  //   predicted pose (the keyframe policy as without the gate).
  double prior_gate_near_m = 0.0;
  bool prior_gate_near_keyframes = false;
  int prior_gate_max_frames = 10;
  // - velocity gate (0: off): a hand moves the camera at most at velocity_gate.max_speed_mps
  //   and changes that velocity by at most max_accel_mps2 (CheckHandMotion). A registered step
  //   beyond either (from the previous pose; the acceleration against the predicted step) was
  //   carried by a walker filling the view: it gives way to the predicted step, or without a
  //   prediction to standing still, and like a prior-gated step makes no keyframe and adds no
  //   measured step to the velocity; at most velocity_gate_max_rejected frames in a row, the
  //   next one is taken as registered. A predicted step faster than max_speed_mps, from the
  //   velocity history or, when it cannot predict, from the fusion's last step, is not used as
  //   prior for the frame (no motion prior, no prior for ICGM and the evidence choice).
  MotionLimits velocity_gate;
  int velocity_gate_max_rejected = 5;
  // - prior reset (prior_reset.h; disagreement_m 0: off): the registered pose further than
  //   prior_reset.disagreement_m from the constant-velocity prediction in prior_reset.frames
  //   frames in a row, the offsets within self_agreement_m of their mean and the registered
  //   poses no faster than max_speed_mps: the frame takes its registered pose, without the
  //   motion prior.
  PriorResetOptions prior_reset;
  // - registration agreement (registration_agreement.h; covariance_scale 0: off): where the
  //   frame's registrations (to its reference and to frame_extra_references nearby keyframes)
  //   agree within max_m / max_deg, the motion prior weighs their mean by the agreement
  //   covariance (their claimed covariance x covariance_scale plus their spread) instead of the
  //   claimed covariance x motion_prior_covariance_scale. With agreement_velocity_only the
  //   velocity history takes the registered pose of agreeing frames only (the fused pose
  //   otherwise); agreement_keyframe_max_postponed > 0 postpones a new keyframe while the
  //   frame's registrations disagree (its pose then mostly the prediction's), at most that many
  //   frames in a row, as long as the reference still registers.
  RegistrationAgreementOptions registration_agreement;
  bool agreement_velocity_only = false;
  int agreement_keyframe_max_postponed = 0;
  // - dynamic_masking: depth residuals after registration mark what moved in front of the
  //   reference; the mask is carried to the next frame, whose features inside it never reach
  //   matching, and keyframes keep only features outside it (verified static).
  bool dynamic_masking = false;
  // Growth of the carried mask for the walkers' own motion between frames (grid cells).
  int mask_growth_cells = 2;
  // A reference keypoint that matched into a dynamic region of this many later frames is
  // dropped from the reference (walkers already in the first frame).
  int reference_dynamic_votes = 2;
  // - residual trend (residual_trend.frames >= 2): while frames register to the same keyframe,
  //   each reference keypoint's match is reprojected with the frame's final motion; keypoints
  //   whose residual grows steadily in one direction, with neighbours drifting alike (a slowly
  //   moving walker), are voted out of the reference before later frames' ICGM and RANSAC,
  //   and the current keypoints matched to them are kept out of a new keyframe
  //   (residual_trend.h).
  ResidualTrendOptions residual_trend;
  // - static_inlier_refit: once the motion is chosen, its depth residuals mark what moved
  //   (depth_consistency.h: the current frame's cells in front of the reference, the reference's
  //   cells the current frame sees through, grown over their surface with fill_max_step_m);
  //   the inliers on either are dropped and the motion registered again on the rest. Where
  //   walkers fill the view every consistent set mixes static points and walkers' points
  //   moving little, so no choice among the sets keeps the walkers out; the residuals of a
  //   mostly static motion show the walkers as a whole.
  bool static_inlier_refit = false;
  // The refit's mask grown over the surface of what moved with this depth step
  // (depth_consistency fill_max_step_m, for the refit only; 0: the masks' own setting).
  double static_refit_fill_max_step_m = 0.0;
  // With static_inlier_refit and select_by_evidence: every hypothesis is refitted on its own
  // static inliers before its evidence is counted, so the choice judges the refitted motions
  // (false: only the chosen one is refitted).
  bool refit_each_hypothesis = false;
  // - dense_refinement: every registration's chosen motion is refined on the whole depth image
  //   (and grey edges), using only pixels its depth residuals verify as static and outside the
  //   dynamic masks of both frames (dense_refinement.h): the room's surfaces constrain the
  //   motion where the few static keypoints leave a pan and a sideways slide alike.
  bool dense_refinement = false;
  // - window (window_frames >= 3, with velocity_prior, without wheels): instead of the motion
  //   prior above, the poses of the last window_frames frames are optimised together over
  //   every registration link of those frames (reference and nearby keyframes, each its own
  //   robust term, covariance times motion_prior_covariance_scale) and a constant-velocity
  //   term (pose_window.h); the frame gets its pose from that window.
  PoseWindowOptions window;
  // - local map (local_map.keyframes > 0): after its registrations, the frame's pose is refined
  //   against the verified-static points of the last local_map.keyframes keyframes (and its
  //   reference) fused in the odom frame, matched by projection and descriptor, by Huber
  //   reprojection error (local_map.h), before the motion prior.
  LocalMapOptions local_map;
  // - map hypothesis (map_hypothesis.keyframes > 0, with select_by_evidence): before its
  //   registrations, the frame is located among the verified-static points of the last
  //   keyframes by descriptor and RANSAC alone, without a start pose (map_hypothesis.h); the
  //   frame pair's matches that agree with that location form one more hypothesis of every
  //   registration, and with map_hypothesis.evidence_weight > 0 each hypothesis's share of the
  //   map correspondences it explains joins the depth and edge evidence.
  MapHypothesisOptions map_hypothesis;
  // - keyframe bundle adjustment (keyframe_ba.keyframes >= 3): when a frame becomes a keyframe,
  //   its pose and those of the last keyframes are adjusted together on their verified-static
  //   points (pixel and depth residuals, Huber; keyframe_bundle_adjustment.h), the oldest held
  //   fixed, after the local map and before the motion prior; the corrected keyframe poses are
  //   the references of the later frames. Keyframes already handed to the callback keep the
  //   pose they were created with.
  KeyframeBaOptions keyframe_ba;
  // - anchors (anchor.keyframes > 0): the run's first keyframes, made with a well-supported
  //   registration before walkers filled the view, are kept beyond the window; every later
  //   frame is also registered to them (the first that gives anchor.min_inliers inliers) and
  //   its pose, after the motion prior, moved anchor.gain of the way to that estimate; the
  //   window's keyframes and the velocity history are re-expressed by the same correction
  //   (anchor.moves_chain), so the chain's drift since the anchor does not add up and the
  //   correction does not become motion (anchor_keyframes.h).
  AnchorOptions anchor;
  DepthConsistencyOptions depth_consistency;
  DenseRefinementOptions dense;

  FeatureOptions features;
  MatcherOptions matcher;
  IcgmOptions icgm;
  RegistrationOptions registration;
  FusionOptions fusion;
  WheelOdometryOptions wheel;
};

// Reads the front-end fields from a `frontend:` section; throws LoadError.
void ReadOptions(const OptionReader& reader, FrontendOptions* options);

// Fills all of `options`: `frontend:`, `registration:`, `fusion:`, `wheel_odometry:` from
// `odometry_root` (config/odometry.yaml) and `features:`, `matcher:`, `icgm:` from `icgm_root`
// (config/icgm.yaml). The two may be the same file. Throws LoadError.
void ReadFrontendOptions(const OptionReader& odometry_root, const OptionReader& icgm_root,
                         FrontendOptions* options);

// A metric model M_x kept as registration reference; handed to the map builder.
struct FrontendKeyframe {
  size_t id = 0;           // 0, 1, 2, ... in creation order
  size_t frame_index = 0;  // index of the frame among all frames given to the front end
  Time stamp;
  Pose3 odom_camera = Pose3::Identity();  // T_odom_camera
  Pose3 odom_base = Pose3::Identity();    // T_odom_base
  // R_x: this keyframe in the previous keyframe's camera frame; and where its last step came
  // from (kNone for the first keyframe).
  Pose3 relative_pose = Pose3::Identity();
  MotionSource relative_source = MotionSource::kNone;
  // Covariance of the registration that placed this keyframe (pose_refinement.h convention);
  // none when it was not placed by vision.
  std::optional<Mat6> covariance;
  // The camera's motion since the previous keyframe as the wheels measured it: the base's
  // T_base(previous)_base(this) moved into the camera frame with the base-to-camera extrinsic
  // (CameraMotionFromBase). None without wheel data covering the span (or across a jump).
  std::optional<Pose3> wheel_camera_motion;
  FeatureSet features;
  // Per keypoint: camera-frame point in metres, NaN when the depth was unusable.
  std::vector<Eigen::Vector3d> points_m;
  // Per keypoint: 1 when ICGM kept its match to the previous reference (the robust features).
  std::vector<uint8_t> robust;
  cv::Mat bgr;
  cv::Mat depth_m;
};
using KeyframePtr = std::shared_ptr<const FrontendKeyframe>;

// Wall time of each stage for one frame, milliseconds.
struct StageTimes {
  double undistort_ms = 0.0;
  double features_ms = 0.0;
  double matching_ms = 0.0;
  double icgm_ms = 0.0;
  double registration_ms = 0.0;
  double fusion_ms = 0.0;
  double total_ms = 0.0;
};

struct FrontendFrameResult {
  size_t frame_index = 0;
  Time stamp;
  Status status = Status::Ok();  // input problems (empty image, wrong depth type)
  Pose3 odom_camera = Pose3::Identity();
  Pose3 odom_base = Pose3::Identity();
  MotionSource source = MotionSource::kNone;
  // Registration to the keyframe (or previous frame on retry); status says why it failed.
  RegistrationResult registration;
  Status wheel_status = Status::Ok();
  bool registered_to_previous = false;  // the keyframe failed and the previous frame was used
  // The velocity history was re-expressed at this new keyframe (velocity_rebase_at_keyframe).
  bool velocity_rebased = false;
  // The motion prior was released (motion_prior_release_frames) for this frame.
  bool motion_prior_released = false;
  bool new_keyframe = false;
  bool revisited_keyframe = false;  // switched to an earlier keyframe of the window
  // The registered step gave way to the constant-velocity prediction (prior_gate_deg / _m);
  // `registration` still holds the registration that was set aside.
  bool prior_gated = false;
  // The registered step was set aside as too fast for a hand (velocity_gate), and the
  // predicted step was not used as prior (too fast for a hand).
  bool velocity_gate_rejected = false;
  bool velocity_gate_dropped_prior = false;
  // The frame took its registered pose without the motion prior (prior_reset).
  bool prior_reset = false;
  // The frame's registrations agreed (registration_agreement), and a new keyframe waited
  // because they did not (agreement_keyframe_max_postponed).
  bool registrations_agreed = false;
  // Largest distance of one of the frame's registrations from their mean (NaN: fewer than two).
  double registration_spread_m = std::nan("");
  bool keyframe_postponed = false;
  // The local map's refined pose was set aside: further from the prediction than the
  // registered pose (local_map.toward_prediction).
  bool local_map_set_aside = false;
  // The pose was corrected by a registration to an anchor keyframe (anchor.keyframes).
  bool anchor_linked = false;
  size_t num_features = 0;
  size_t num_matches = 0;    // ratio-test matches to the reference
  size_t num_icgm_kept = 0;  // matches given to registration
  // Current-frame pixels of the matches given to registration, in registration order:
  // registration.inlier_indices index into it (e.g. to check matches against a dynamic mask).
  std::vector<cv::Point2f> registered_px;
  // The reference's pixels of the same matches, and the reference frame's index (diagnosis
  // against ground truth; unset when nothing was registered).
  std::vector<cv::Point2f> registered_reference_px;
  std::optional<size_t> reference_index;
  // select_by_evidence: every hypothesis the registration's evidence choice judged, and the
  // index of the chosen one (-1: no choice; the registration above is the chosen one after
  // static_inlier_refit).
  std::vector<JudgedHypothesis> hypotheses;
  int chosen_hypothesis = -1;
  // The predicted motion as T_reference_current (unset without a prediction or reference).
  std::optional<Pose3> predicted_reference_current;
  // residual_trend: the reference keypoints voted out by this frame (reference pixels).
  std::vector<cv::Point2f> trend_voted_reference_px;
  StageTimes times;
};

}  // namespace icgm
