// ROS-free RGB-D visual odometry front end of the hybrid SLAM (thesis ch. 6.1.1.1):
//   features (FeatureExtractor) -> putative matches (DescriptorMatcher, ratio test)
//   -> robust matches (RunIcgm, thesis Algorithm 1; skipped with use_icgm = false)
//   -> 6-D rigid transformation (RegisterRgbd: depth, RANSAC + Horn, refinement)
//   -> motion source choice and pose accumulation (OdometryFusion, eq. 6.1).
//
// Frame-to-keyframe registration: every frame is registered to the current keyframe (the metric
// model M_(x-phi)); a frame becomes the next keyframe when its inliers to the keyframe drop below
// keyframe_min_inliers, the motion since the keyframe exceeds the keyframe_max_* bounds, phi
// reaches max_keyframe_interval_phi, or the registration failed (then the pose comes from wheel
// odometry or constant velocity, and the frame restarts the chain). Registering to a keyframe
// instead of the previous frame avoids integrating the noise of every single step.
// Before a new keyframe is made, the most recent keyframe_window keyframes near the current
// pose (revisit_max_*) are tried as reference: when the camera comes back to a place it saw a
// moment ago, it is registered to that keyframe again instead of extending the chain, so the
// odometry does not drift while moving back and forth (a local map, not loop closure: no past
// pose is corrected, and only recent keyframes near the current estimate are considered).
// A new keyframe (and, with frame_extra_references > 0, every frame) is also registered to a few
// other nearby window keyframes; its pose is the information-weighted mean of the estimates
// (registration covariances, pose_refinement.h), which averages the noise of single links.
//
// Keyframes are handed out through a callback (the map builder's metric models) and
// last_keyframe(). Not thread-safe: call from one thread.
#pragma once

#include <algorithm>
#include <deque>
#include <functional>
#include <memory>
#include <optional>
#include <utility>

#include "core/common/camera.h"
#include "core/features/lens_undistortion.h"
#include "core/odometry/frontend_types.h"
#include "core/odometry/hypothesis_evidence.h"
#include "core/odometry/map_hypothesis.h"
#include "core/odometry/residual_trend.h"
#include "core/odometry/velocity_history.h"

namespace icgm {

class RgbdFrontend {
 public:
  using KeyframeCallback = std::function<void(const KeyframePtr&)>;

  RgbdFrontend(const FrontendOptions& options, const CameraIntrinsics& intrinsics);
  ~RgbdFrontend();

  // Wheel odometry T_odom_base samples, in time order; see WheelOdometryBuffer::Add.
  Status AddWheelOdometry(Time stamp, const Pose3& odom_base);

  // Processes one RGB-D frame: `bgr` 8-bit BGR or gray, `depth_m` CV_32FC1 metres registered to
  // the colour image (NaN/0 invalid). Stamps must increase. Bad input never throws: the frame
  // gets a non-ok status and its pose from the fallbacks.
  // When distortion coefficients are configured, both images are first resampled to the ideal
  // pinhole camera of `intrinsics` (keyframes keep the undistorted images).
  // `depth_stamp`: when the depth image was stamped (default: `stamp`), for
  // compensate_depth_timing.
  FrontendFrameResult ProcessFrame(Time stamp, const cv::Mat& bgr, const cv::Mat& depth_m,
                                   std::optional<Time> depth_stamp = std::nullopt);
  // Same with features extracted elsewhere (the feature extraction nodelet), so the
  // distributed pipeline registers frame-to-keyframe like the offline one. `depth_stamp` as in
  // ProcessFrame. `bgr` (optional, the raw colour image the features came from) gives
  // select_by_evidence its edge evidence as ProcessFrame has it; without it keyframes carry no
  // image and hypotheses are scored on depth alone. `keypoints_undistorted`: the features were
  // extracted on the image LensUndistortion made of the raw one, as ProcessFrame extracts them
  // (equal results); false: on the raw image, and their keypoints are moved instead.
  FrontendFrameResult ProcessFeatures(Time stamp, FeatureSet features, const cv::Mat& depth_m,
                                      std::optional<Time> depth_stamp = std::nullopt,
                                      const cv::Mat& bgr = cv::Mat(),
                                      bool keypoints_undistorted = false);

  // Called with each new keyframe, right after it is created.
  void SetKeyframeCallback(KeyframeCallback callback) { keyframe_callback_ = std::move(callback); }

  const KeyframePtr& last_keyframe() const { return keyframe_; }
  // Features of the last frame processed, as its keyframe would keep them (undistorted; a
  // keyframe's without its dynamic regions), and its stamp; nullptr before the first frame.
  const FeatureSet* last_frame_features(Time* stamp = nullptr) const;
  size_t num_keyframes() const { return num_keyframes_; }
  size_t num_frames() const { return frame_count_; }
  const FusionStats& fusion_stats() const { return fusion_.stats(); }
  const Pose3& odom_camera() const { return fusion_.odom_camera(); }
  const FrontendOptions& options() const { return options_; }
  const CameraIntrinsics& intrinsics() const { return intrinsics_; }

 private:
  struct Frame;
  struct Attempt;
  // `features` null: extract from `bgr`.
  FrontendFrameResult Process(Time stamp, const cv::Mat& bgr, const cv::Mat& depth_m,
                              FeatureSet* features, std::optional<Time> depth_stamp,
                              bool keypoints_undistorted = false);
  // Capture instant of the depth minus that of the colour image (s); 0 when
  // compensate_depth_timing is off or the difference is below depth_timing_min_s.
  double DepthTimeOffsetS(Time stamp, Time depth_stamp) const;

  struct MatchSet;
  // Registers the matches flagged in `use` with RANSAC seed registration.rng_seed + seed_offset.
  using SubsetRegistration =
      std::function<void(const std::vector<uint8_t>& use, uint64_t seed_offset, Attempt* out)>;
  Attempt RegisterTo(const Frame& reference, const Frame& current, StageTimes* times) const;
  // residual_trend: the frame's matches to its reference (attempt) reprojected with its final
  // pose join the reference's residual tracks; returns the reference pixels voted out now, and
  // marks the current keypoints matched to voted-out ones (trend_excluded).
  std::vector<cv::Point2f> ObserveResidualTrend(const Attempt& attempt, Frame* current);
  // select_by_evidence: further hypotheses from the same matches (the set `first_use`'s
  // registration left out; the matches agreeing with `predicted`, and with `map_predicted`,
  // where the current frame's location in the local map puts them; `first_use` registered with
  // further RANSAC seeds, evidence_ransac_runs); the one whose motion the whole frame's depth
  // agrees with most replaces *best.
  void ChooseByEvidence(const Frame& reference, const Frame& current, const MatchSet& all,
                        const std::vector<Eigen::Vector2d>& predicted,
                        const std::vector<Eigen::Vector2d>& map_predicted,
                        const std::vector<uint8_t>& first_use,
                        const SubsetRegistration& register_subset, Attempt* best) const;
  // static_inlier_refit: drops the inliers of *a on what its motion's depth residuals mark as
  // moved (current or reference side) and registers the rest again; *a keeps its first result
  // when nothing was dropped or the rest does not register.
  void RefitOnStaticInliers(const Frame& reference, const Frame& current, const MatchSet& all,
                            const SubsetRegistration& register_subset, Attempt* a) const;
  // Window keyframes (not the reference) within the revisit bounds of `predicted`, nearest
  // first by normalized translation + rotation.
  std::vector<std::shared_ptr<const Frame>> NearbyKeyframes(const Pose3& predicted) const;
  // Tries the window's keyframes near `predicted` (nearest first); on success sets *chosen.
  Attempt RegisterToNearbyKeyframe(const Frame& current, const Pose3& predicted, StageTimes* times,
                                   std::shared_ptr<const Frame>* chosen) const;
  KeyframePtr MakeKeyframe(const Frame& frame, const cv::Mat& bgr, const Attempt* attempt,
                           MotionSource source);
  // Pose of a frame from its registration to the reference (`primary_pose` =
  // T_odom_cur from `primary`) and to up to `max_references` other nearby window keyframes.
  // `links` (optional) gets each estimate used with its registration covariance, the
  // primary's first.
  Pose3 FuseWithNearbyKeyframes(const Frame& current, const Pose3& primary_pose,
                                const Attempt& primary, int max_references, StageTimes* times,
                                std::vector<PoseLink>* links = nullptr) const;
  // select_across_references: every hypothesis of those registrations is judged by the summed
  // depth and edge evidence of all the references and the previous frame; the winner is
  // averaged with the links' hypotheses that agree with it (reference_agreement_*).
  Pose3 SelectAcrossReferences(const Frame& current, const Pose3& primary_pose,
                               const Attempt& primary,
                               const std::vector<std::shared_ptr<const Frame>>& near,
                               int max_references, StageTimes* times) const;
  // reference_agreement_*: the pose `other` (from another keyframe) lies within the bounds of
  // `primary` (from the reference); always true when the bound is 0.
  bool AgreesWithReference(const Pose3& primary, const Pose3& other) const;
  // motion_prior_sigma_*: the information-weighted mean of the constant-velocity prediction
  // and the vision estimate `measured` (its covariance, already scaled), the prior's sigmas
  // times `sigma_scale`.
  Pose3 FuseWithPrediction(const Pose3& predicted, const Pose3& measured, const Mat6& covariance,
                           double sigma_scale) const;
  // previous_ (just set) joins the velocity history (velocity_prior_steps); `vision_pose`:
  // its pose as registered, before the motion prior (velocity_from_vision).
  void RememberPrevious(const std::optional<Pose3>& vision_pose = std::nullopt);
  // depth_timing_averaged_velocity in force: the depth timing's and rolling shutter's velocity
  // is the velocity history's.
  bool AveragedTimingVelocity() const;
  // velocity_rebase_*: at a new keyframe `current` (fused pose set, `registered_pose` as its
  // registration `attempt` measured it, `frames_since_reference` frames after its reference),
  // the correction the velocity history is to be re-expressed by once the frame joins it, or
  // none where the options leave the history as it is.
  std::optional<Pose3> VelocityRebaseAtKeyframe(const Frame& current, const Attempt& attempt,
                                                const Pose3& registered_pose,
                                                size_t frames_since_reference);
  // The whole frame's evidence for `current` at the registered and at the fused pose (depth and
  // edge agreement against the reference and the previous frame, each cue normalized over the
  // two): true where the registered pose explains more of it.
  bool RegisteredPoseExplainsMore(const Frame& current, const Frame& reference,
                                  const Pose3& registered_pose) const;
  // Depth and edge agreement of `current`, placed at `odom_cur`, with each of `judges` (grid
  // pixels whose depth, edge pixels whose grey value the pose explains), summed over them.
  HypothesisEvidence AgreementWithJudges(const std::vector<const Frame*>& judges,
                                         const Frame& current, const Pose3& odom_cur,
                                         const DepthConsistencyOptions& options) const;
  double PixelSigma(const cv::KeyPoint& keypoint) const;
  // local_map.keyframes > 0: `odom_camera` (the frame's registered pose) refined against the
  // verified-static points of the last keyframes and the reference (local_map.h).
  LocalMapTrackResult TrackAgainstLocalMap(const Frame& current, const Pose3& odom_camera) const;
  // The verified-static points of the last `max_keyframes` keyframes and the reference, in the
  // odom frame (local_map.h).
  LocalMapPoints BuildLocalMap(int max_keyframes) const;
  // The last `max_keyframes` keyframes of the window, and the reference when not among them.
  std::vector<std::shared_ptr<const Frame>> RecentKeyframes(int max_keyframes) const;
  // A keyframe's verified-static points in the odom frame, with its capture time.
  TimedMapPoints KeyframeMapPoints(const Frame& keyframe) const;
  // The keyframe's keypoints lifted by its depth (`use`: lifted), and which of them are static
  // (walkers not seen leaving them, dynamic_votes).
  void LiftKeyframe(const Frame& keyframe, std::vector<Vec3>* points,
                    std::vector<uint8_t>* use) const;
  std::vector<uint8_t> StaticKeypoints(const Frame& keyframe,
                                       const std::vector<uint8_t>& lifted) const;
  // KeyframeMapPoints kept between frames while the keyframe's pose and static keypoints stay the
  // same, with an id that changes when they do (map_hypothesis_cache_).
  PersistenceCache::Keyframe CachedKeyframeMapPoints(
      const std::shared_ptr<const Frame>& keyframe) const;
  // One pixel sigma per keypoint of `frame` (PixelSigma).
  std::vector<double> PixelSigmas(const Frame& frame) const;
  // map_hypothesis.keyframes > 0: `current` located in the local map of the last keyframes by
  // descriptor and RANSAC, without a start pose (map_hypothesis.h); `viewing_frame` only fixes
  // the frame the reprojection test is made in.
  std::shared_ptr<const MapHypothesis> LocateInMap(const Frame& current,
                                                   const Pose3& viewing_frame) const;
  // map_hypothesis options with the registration's depth tolerances, iterations and seed.
  MapHypothesisOptions MapSupportOptions() const;
  // keyframe_ba: `current` (about to become a keyframe, at `odom_camera`) and the last window
  // keyframes adjusted together (keyframe_bundle_adjustment.h); the window keyframes take their
  // corrected poses, and the current frame's is returned (none when the adjustment failed).
  std::optional<Pose3> AdjustWithKeyframes(const Frame& current, const Pose3& odom_camera) const;
  // anchor.keyframes > 0: `current` registered to the anchors, the first whose registration
  // has anchor.min_inliers inliers (T_odom_camera and inliers); none when no anchor gives one.
  struct AnchorEstimate {
    Pose3 odom_camera;
    int inliers = 0;
  };
  std::optional<AnchorEstimate> RegisterToAnchors(const Frame& current, StageTimes* times) const;
  bool IsAnchor(const std::shared_ptr<const Frame>& keyframe) const {
    return std::find(anchors_.begin(), anchors_.end(), keyframe) != anchors_.end();
  }
  bool WindowOn() const { return options_.window.frames >= 3; }
  // The frame's registrations are compared (registration agreement or one of its uses).
  bool AgreementOn() const {
    return options_.registration_agreement.on() || options_.agreement_velocity_only ||
           options_.agreement_keyframe_max_postponed > 0;
  }
  bool NeedsNewKeyframe(const Attempt& attempt, const Frame& current) const;

  FrontendOptions options_;
  CameraIntrinsics intrinsics_;
  std::unique_ptr<FeatureExtractor> extractor_;
  DescriptorMatcher matcher_;
  WheelOdometryBuffer wheel_;
  OdometryFusion fusion_;
  LensUndistortion undistortion_;  // inactive for a camera without distortion
  KeyframeCallback keyframe_callback_;
  bool pyramid_octaves_ = false;  // keypoint octave = ORB pyramid level

  KeyframePtr keyframe_;                             // last keyframe created
  std::shared_ptr<const Frame> reference_;           // keyframe frames are registered to
  size_t reference_since_ = 0;                       // frame index when reference_ was adopted
  std::optional<size_t> first_keyframe_index_;       // frame index of the run's first keyframe
  // Consecutive frames registered to the frame just before them (motion_prior_release_frames).
  int previous_referenced_in_row_ = 0;
  // Over those frames: the sum of the registered steps' translation offsets from the predicted
  // steps, and the sum of their norms (motion_prior_release_persistence).
  Vec3 release_offset_sum_ = Vec3::Zero();
  double release_offset_norm_sum_ = 0.0;
  int keyframes_postponed_in_row_ = 0;  // new keyframes postponed in a row (agreement)
  int prior_gated_in_row_ = 0;  // consecutive frames whose registration gave way (prior gate)
  std::deque<std::shared_ptr<const Frame>> window_;  // recent keyframes, oldest first
  // Anchor keyframes (anchor.keyframes), oldest first, and whether the set is closed.
  std::vector<std::shared_ptr<const Frame>> anchors_;
  bool anchors_closed_ = false;
  std::unique_ptr<Frame> previous_;
  // map_hypothesis: each keyframe's map points and the persistence test's results, recomputed
  // only when the keyframe window, a keyframe's pose or its static keypoints change.
  struct MapHypothesisCache;
  mutable std::unique_ptr<MapHypothesisCache> map_hypothesis_cache_;
  // The frame before previous_ (stamp, T_odom_camera): with previous_, the camera velocity.
  std::optional<std::pair<Time, Pose3>> before_previous_;
  size_t num_keyframes_ = 0;
  size_t frame_count_ = 0;
  bool has_stamp_ = false;
  Time last_stamp_;
  std::optional<Time> stamp_jump_;  // a frame stamped far ahead, waiting for confirmation
  // Recent frame poses for the constant-velocity prediction over velocity_prior_steps.
  VelocityHistory velocity_history_;
  // The registered steps chained on their own, and their velocity history
  // (motion_prior_release_registered_velocity).
  Pose3 registered_track_ = Pose3::Identity();
  VelocityHistory registered_velocity_history_;
  int velocity_gate_rejected_in_row_ = 0;  // frames in a row whose step the velocity gate set aside
  PriorResetDetector prior_reset_;
  // Translation of the last keyframe's fused-minus-registered offset (velocity rebase).
  std::optional<Vec3> last_rebase_offset_m_;
  // The last frames' poses optimised together (window.frames >= 3).
  PoseWindow pose_window_;
  // Residual tracks of the reference keyframe's matches (residual_trend).
  ResidualTrend residual_trend_;
};

}  // namespace icgm
