// Monocular visual odometry with ICGM-filtered matches (thesis ch. 6.2, Fig. 6.12): one camera,
// no depth.
//   features (FeatureExtractor) -> ratio-test matches (DescriptorMatcher) -> robust matches
//   (RunIcgm, thesis Algorithm 1; skipped with use_icgm = false) -> geometry:
//  - initialization: matches between a reference frame and the current one give the essential
//    matrix (five-point RANSAC) and the relative motion (two_view.h); once the median parallax
//    of the triangulated inliers reaches init_min_parallax_deg the two frames become the first
//    keyframes and the triangulated points the local map;
//  - tracking: each frame is matched to the newest keyframes; matches to keypoints that carry a
//    map point give 2D-3D correspondences for PnP in RANSAC (pnp_pose.h), with the
//    constant-velocity prediction as alternative seed. With icgm.motion_prior (default), ICGM
//    compares those matches with where their map points reproject under the constant-velocity
//    prediction, so a walker filling the view cannot be the consistent set. The other points
//    of the local map (the points of the newest local_map_keyframes keyframes) are then
//    projected with the pose and matched by descriptor near their projection, and the pose is
//    refined on all correspondences;
//  - relocalization (relocalize): a frame that cannot be tracked so is matched again, with all
//    ratio-test matches to several keyframes plus the local map projected with the predicted
//    pose in a wide radius, before it counts as lost (blurred frames keep few matches);
//  - keyframes: when the tracked map points drop (keyframe_* options) the frame becomes a
//    keyframe, its ICGM matches to the previous keyframe without a map point are triangulated,
//    and a windowed bundle adjustment (core/optimization, reprojection only) refines the newest
//    keyframes and their points with the oldest ones of the window held fixed; older keyframes
//    of the local map that see the window's points join as fixed cameras (ba_covisible_fixed),
//    so the scale of the map is carried from keyframe to keyframe;
//  - tracking loss: after lost_frames_before_reset frames without a pose the map is dropped and
//    the odometry initializes again from the last pose (or that pose carried on at the last
//    map's constant velocity, reset_bridge_max_s); the new map's scale is taken from the
//    speed before the loss (carry_scale_over_reset) or from the wheels.
// Scale: a monocular map has an unknown scale. With wheel odometry (AddWheelOdometry and the
// base-to-camera extrinsic) the initial baseline is set to the wheels' distance and the map is
// pulled toward the wheel scale at every keyframe; without, the first baseline has length 1 and
// every result says scale_known = false.
// Not thread-safe: call from one thread.
#pragma once

#include <deque>
#include <memory>
#include <optional>
#include <unordered_map>
#include <unordered_set>
#include <vector>

#include <opencv2/core.hpp>

#include "core/common/camera.h"
#include "core/common/pose.h"
#include "core/common/status.h"
#include "core/common/time.h"
#include "core/features/descriptor_matcher.h"
#include "core/features/feature_extractor.h"
#include "core/mono/mono_options.h"
#include "core/mono/pnp_pose.h"
#include "core/odometry/wheel_odometry_buffer.h"

namespace icgm {

enum class MonoState { kInitializing, kTracking, kLost };
const char* MonoStateName(MonoState state);

// Thread CPU time (ms) per stage of one frame.
struct MonoStageTimes {
  double features_ms = 0.0;
  double matching_ms = 0.0;
  double icgm_ms = 0.0;
  double geometry_ms = 0.0;  // essential matrix or PnP
  double mapping_ms = 0.0;   // keyframe, triangulation, bundle adjustment
  double total_ms = 0.0;
};

struct MonoFrameResult {
  size_t frame_index = 0;
  Time stamp;
  // Why the frame got no pose (input problem, too few features, failed geometry); ok with a pose.
  Status status = Status::Ok();
  MonoState state = MonoState::kInitializing;  // after this frame
  bool has_pose = false;
  Pose3 world_camera = Pose3::Identity();  // T_world_camera, valid with has_pose
  // The map was (re-)initialized on this frame; `reference` is then the pose given to the
  // initialization's reference frame (earlier frame, stamp reference_stamp).
  bool initialized = false;
  Time reference_stamp;
  Pose3 reference_world_camera = Pose3::Identity();
  bool new_keyframe = false;
  bool reset = false;  // the map was dropped after a tracking loss on this frame
  // Tracked only by the relocalization against the whole local map (the newest keyframes'
  // robust matches were not enough).
  bool relocalized = false;
  // ... against the last good keyframe (relocalize_good_keyframe_points).
  bool relocalized_on_good_keyframe = false;
  // The map's metric scale came from the wheels; false: arbitrary (first baseline = 1 unit or
  // carried over a reset).
  bool scale_known = false;
  size_t num_features = 0;
  size_t num_matches = 0;    // ratio-test matches to the reference keyframe(s) / frame
  size_t num_icgm_kept = 0;  // matches given to the geometry
  size_t num_inliers = 0;    // essential-matrix or PnP inliers
  // Inliers over the correspondences given to the geometry (essential matrix or PnP).
  double inlier_ratio = 0.0;
  size_t map_points = 0;
  // Thr of the ICGM motion prior on this frame's tracking matches (0: no prior applied).
  double prior_threshold = 0.0;
  // Pixels in this frame of the matches given to the geometry after ICGM (tracking: matches to
  // the newest keyframe's map points; initialization: the two-view matches), e.g. to count
  // how many lie on moving objects.
  std::vector<Eigen::Vector2d> robust_pixels;
  // Indices into robust_pixels of the geometry's inliers (first PnP RANSAC or essential matrix).
  std::vector<int> robust_inliers;
  // Pixels in this frame of the tracked pose's inliers (after the local map's projection), and
  // the depth of their map points in this camera (map units; with a depth image it gives the
  // map's scale at this frame).
  std::vector<Eigen::Vector2d> tracked_pixels;
  std::vector<double> tracked_depths;
  // Tracking: the map point of each correspondence of the tracked pose (inliers and outliers).
  std::vector<int> pose_point_ids;
  // Keyframe: pixels in this frame of the map points it created.
  std::vector<Eigen::Vector2d> new_point_pixels;
  // Tracking: the ratio-test matches to the newest keyframe, by pixel in this frame, split by
  // whether the keyframe's keypoint carries a map point; the indices of those ICGM kept (all
  // without ICGM). Shows which matches ICGM drops, e.g. how many lie on moving objects.
  std::vector<Eigen::Vector2d> to_last_point_pixels, to_last_candidate_pixels;
  std::vector<int> to_last_point_kept, to_last_candidate_kept;
  // Map points deleted on this frame as moving (cull_outlier_frames) and new points not added
  // because no earlier view showed them where they project (new_point_confirm_px), they lie
  // in a moving region (dynamic_mask_radius_px) or outside the long-baseline ICGM group
  // (new_point_icgm_baseline_keyframes).
  size_t culled_points = 0;
  size_t rejected_new_points = 0;
  // Their pixels in this frame (a culled point: where it was matched as an outlier).
  std::vector<Eigen::Vector2d> culled_pixels, rejected_new_point_pixels;
  // Keyframe: new map points triangulated with older keyframes (new_point_extra_keyframes).
  size_t extra_new_points = 0;
  // Relocalized frame: map points that the pose's projection search would have matched a
  // second time, at another keypoint, had it not skipped the points the relocalization's
  // projection search already matched (each map point is matched at most once per frame).
  size_t duplicate_points_skipped = 0;
  // Map points whose match to a reference keyframe ICGM rejected (no kept match gave them), and
  // the pixels of those the projection search matched again as inliers of the tracked pose
  // (none with projection_skips_icgm_rejected).
  size_t icgm_rejected_points = 0;
  std::vector<Eigen::Vector2d> icgm_rejected_readmitted_pixels;
  // Pixels in this frame of the ICGM-rejected map points (one match each).
  std::vector<Eigen::Vector2d> icgm_rejected_pixels;
  // pnp_verified_min_keyframes: indices into robust_pixels of the correspondences whose map
  // point is verified (persistent), and whether the pose from them alone was taken.
  std::vector<int> robust_verified;
  bool pnp_on_verified = false;
  // track_icgm_baseline_frames: the frame's ratio-test matches with the frame that many frames
  // before, by pixel in this frame, and the indices of those in ICGM's largest consistent group
  // (empty: option off or no older frame); the pixels of the correspondences not given to PnP
  // because their keypoint fell outside that group.
  std::vector<Eigen::Vector2d> long_baseline_pixels;
  std::vector<int> long_baseline_kept;
  std::vector<Eigen::Vector2d> long_baseline_dropped_pixels;
  // ... the older frame was in range but the camera had moved too far against the scene depth
  // (track_icgm_baseline_max_translation_depth_ratio): no check this frame.
  bool long_baseline_gated = false;
  // Keyframe with scene_depth_band: the factor the local map was scaled by to hold the scene
  // depth (1: within the band, or the option off).
  double scene_depth_scale = 1.0;
  // rotation_only_parallax_deg: the median parallax (deg) the rotation between the newest
  // keyframe and this frame leaves among the matches given to the geometry (0: not measured),
  // and whether the frame was posed by that rotation at the keyframe's position.
  double parallax_deg = 0.0;
  bool rotation_only = false;
  MonoStageTimes times;
};

class MonoOdometry {
 public:
  MonoOdometry(const MonoOptions& options, const CameraIntrinsics& intrinsics);
  ~MonoOdometry();

  // Wheel odometry: the extrinsic base_link -> camera first, then T_odom_base samples in time
  // order. Without both, the scale stays unknown.
  void SetBaseToCamera(const Pose3& base_to_camera) { base_to_camera_ = base_to_camera; }
  Status AddWheelOdometry(Time stamp, const Pose3& odom_base);

  // One image (8-bit grey, BGR or BGRA), stamps increasing. Never throws.
  MonoFrameResult ProcessFrame(Time stamp, const cv::Mat& image);

  MonoState state() const { return state_; }
  size_t num_keyframes() const { return num_keyframes_; }
  size_t num_resets() const { return num_resets_; }
  size_t num_map_points() const { return points_.size(); }
  const MonoOptions& options() const { return options_; }

 private:
  struct Frame;
  struct Keyframe;
  struct MapPoint;
  struct Matches;
  // 2D-3D correspondences of a frame with the local map, each keypoint and map point once.
  struct Correspondences {
    std::vector<Eigen::Vector3d> points;
    std::vector<Eigen::Vector2d> pixels;
    std::vector<int> point_of, keypoint_of;
    std::vector<uint8_t> keypoint_used;
    std::unordered_set<int> point_used;
    // The first `num_collected` come from keyframe matches, the others from a projection search.
    size_t num_collected = 0;
    // Map points whose match ICGM rejected and that no kept match gave.
    // With the keypoint in this frame of (one of) its rejected matches.
    std::unordered_map<int, int> icgm_rejected;
  };

  Frame MakeFrame(Time stamp, const cv::Mat& image, MonoStageTimes* times) const;
  // Ratio-test matches a -> b, then ICGM when `robust` and use_icgm. With icgm.motion_prior,
  // `keyframe` (= a) and the `predicted` pose of b, ICGM runs with the motion prior on the
  // matches whose keypoint in a carries a map point.
  // `given`: ratio-test matches a -> b already computed (not matched again).
  Matches MatchFrames(const Frame& a, const Frame& b, MonoStageTimes* times, bool robust,
                      const Keyframe* keyframe = nullptr,
                      const std::optional<Pose3>& predicted = std::nullopt,
                      const std::vector<cv::DMatch>* given = nullptr) const;
  // Correspondences from the newest `refs` keyframes of the window (matches to the newest go
  // to `to_last`). `ratio_matches`: the ratio-test matches per keyframe (newest first); those
  // it holds are used, the others computed and appended.
  void Collect(const Frame& frame, int refs, bool robust, const std::optional<Pose3>& predicted,
               Correspondences* c, Matches* to_last, MonoFrameResult* result,
               std::vector<std::vector<cv::DMatch>>* ratio_matches = nullptr) const;
  void TryInitialize(Frame frame, MonoFrameResult* result);
  // Map points not in `used` projected with `world_camera` and matched (binary descriptors)
  // to untaken keypoints within radius_px; appends the correspondences, adds their points to
  // `used` and their keypoints to `taken` (a map point is matched at most once per frame) and
  // returns how many were found.
  size_t SearchByProjection(const Frame& frame, const Pose3& world_camera, double radius_px,
                            std::unordered_set<int>* used, std::vector<uint8_t>* taken,
                            std::vector<Eigen::Vector3d>* points,
                            std::vector<Eigen::Vector2d>* pixels, std::vector<int>* point_of,
                            std::vector<int>* keypoint_of) const;
  void Track(Frame frame, MonoFrameResult* result);
  // pnp_verified_min_keyframes: the map point was seen in place by enough keyframes over
  // enough time.
  bool Verified(int point_id) const;
  // rotation_only_parallax_deg: the rotation between the newest keyframe `last` and `frame`
  // from the matches `to_last` gives to the geometry; true when its median parallax is below
  // the option's, with *world_camera then at the keyframe's position, turned by that rotation.
  // Sets result->parallax_deg (option on, without wheels).
  bool LowParallaxRotation(const Frame& frame, const Keyframe& last, const Matches& to_last,
                           Pose3* world_camera, MonoFrameResult* result) const;
  // Tracking's first PnP on `c`: RANSAC on all correspondences; with pnp_verified_min_keyframes
  // also on the verified ones alone (when there are enough), refined on its inliers among all,
  // and that pose instead when it fits more of the verified correspondences.
  PnpResult TrackingPnp(const Correspondences& c, const PnpOptions& pnp,
                        const std::optional<Pose3>& predicted, MonoFrameResult* result) const;
  // How many of the map points in `matched` the projection search with `used` and `taken`
  // would match again (at other keypoints).
  size_t CountDuplicates(const Frame& frame, const Pose3& world_camera,
                         std::unordered_set<int> used, std::vector<uint8_t> taken,
                         const std::vector<int>& matched) const;
  // Relocalization against the local map (all ratio-test matches to the newest
  // relocalize_keyframes keyframes and the map projected with `predicted` within
  // relocalize_radius_px, PnP RANSAC with relocalize_pnp_iterations); `c` gets the
  // correspondences, `to_last` the matches to the newest keyframe. `ratio_matches` as in
  // Collect (the frame's matches to the keyframes tracking already matched).
  PnpResult Relocalize(const Frame& frame, const std::optional<Pose3>& predicted,
                       Correspondences* c, Matches* to_last, MonoFrameResult* result,
                       std::vector<std::vector<cv::DMatch>>* ratio_matches = nullptr) const;
  void AddKeyframe(const Frame& frame, const Pose3& world_camera,
                   const std::vector<int>& tracked_point, const Matches& to_last,
                   MonoFrameResult* result);
  // cull_outlier_frames: counts, per correspondence's map point, the tracked frames in a row
  // it was not an inlier of the pose, and deletes the points that reached the count.
  void CullMovingPoints(const std::vector<int>& point_of,
                        const std::vector<Eigen::Vector2d>& pixels,
                        const std::vector<uint8_t>& inlier, MonoFrameResult* result);
  // Whether cull_outlier_frames and new_point_confirm_px act on this input
  // (moving_point_checks_with_wheels, or no wheel odometry given).
  bool MovingPointChecksApply() const;
  // dynamic_mask_radius_px: whether `px` lies in a moving region of this frame.
  bool InMovingRegion(const Eigen::Vector2d& px) const;
  // new_point_confirm_px: false when one of `views` shows `world` in front of it but no
  // keypoint like `descriptor` (one row) near its projection; true when one shows it there
  // or none sees it. With new_point_contradiction_px: false only when no view shows it near
  // its projection and one shows its most similar keypoint farther away.
  bool SeenInEarlierView(const Eigen::Vector3d& world, const cv::Mat& descriptor,
                         const std::vector<std::pair<const Frame*, Pose3>>& views) const;
  // Median depth in the camera at `world_camera` of the map points `tracked_point` (per
  // keypoint, -1 none) names; nullopt with fewer than 10.
  std::optional<double> MedianTrackedDepth(const Frame& frame, const Pose3& world_camera,
                                           const std::vector<int>& tracked_point) const;
  // new_point_min_baseline_depth_ratio: index in window_ of the keyframe a new keyframe at
  // `world_camera` triangulates its new points with (the newest when the option is off).
  size_t NewPointReference(const Frame& frame, const Pose3& world_camera,
                           const std::vector<int>& tracked_point) const;
  // new_point_extra_keyframes: indices in window_ (newest first) of the keyframes older than
  // `first` that a new keyframe at `world_camera` also triangulates new points with.
  std::vector<size_t> ExtraNewPointReferences(const Frame& frame, const Pose3& world_camera,
                                              const std::vector<int>& tracked_point,
                                              size_t first) const;
  // Per match of `to_last`: 1 when it may give a new map point (new_points_from_map_group).
  std::vector<uint8_t> NewPointCandidates(const Keyframe& last, const Frame& frame,
                                          const Pose3& world_camera,
                                          const std::vector<int>& tracked_point,
                                          const Matches& to_last) const;
  // new_point_icgm_baseline_keyframes: per match of `to_last`, 1 when its keypoint in `frame`,
  // matched from an older keyframe, lies outside the ICGM group grown from the tracked static
  // map between that keyframe and `frame` (empty: option off or no group).
  std::vector<uint8_t> OutsideLongBaselineGroup(const Frame& frame,
                                                const std::vector<int>& tracked_point,
                                                const Matches& to_last) const;
  // track_icgm_baseline_frames: per keypoint of `frame`, 1 when its match with the buffered
  // older frame lies outside ICGM's largest consistent group (with the rotation prior: the one
  // holding most matches that agree with it; empty: option off, no older frame in range or no
  // group, or skipped by track_icgm_baseline_max_translation_depth_ratio, the depth from `c`'s
  // map points); fills result->long_baseline_pixels / _kept / _gated.
  std::vector<uint8_t> MovingOverLongBaseline(const Frame& frame,
                                              const std::optional<Pose3>& predicted,
                                              const Correspondences& c,
                                              MonoFrameResult* result) const;
  // Removes from `c` the correspondences whose keypoint `moving` flags (their pixels to
  // result->long_baseline_dropped_pixels).
  static void DropMovingCorrespondences(const std::vector<uint8_t>& moving, Correspondences* c,
                                        MonoFrameResult* result);
  // new_points_from_prior: the matches of `to_last` ICGM keeps with the motion prior of the
  // frame's tracked pose `world_camera`; nullopt when the keyframe has too few map points.
  std::optional<std::vector<uint8_t>> PriorCandidates(const Keyframe& last, const Frame& frame,
                                                      const Pose3& world_camera,
                                                      const Matches& to_last) const;
  void AdjustWindow();
  void ApplyWheelScale();
  // scene_depth_band: the newest keyframe's median depth of the `tracked_point`s held within
  // the band about map_depth_ (the local map scaled about the newest keyframe); returns the
  // factor.
  double HoldSceneDepth(const std::vector<int>& tracked_point);
  // The local map, the poses of the prediction and the last tracked frame's pose scaled by `f`
  // about `centre` (a similarity: every view of the map keeps its reprojections).
  void ScaleLocalMap(const Eigen::Vector3d& centre, double f);
  // Wheel distance (m) the camera moved between two stamps; nullopt without usable wheels.
  std::optional<double> WheelDistance(Time from, Time to) const;
  void DropOldKeyframes();
  void Reset(MonoFrameResult* result);
  // Pose given to a new map's reference frame at `stamp`: the last tracked pose, carried on at
  // the last map's constant velocity with reset_bridge_max_s (identity before any pose).
  Pose3 ReferencePose(Time stamp) const;
  // Constant velocity, or the wheels' motion with wheel_prediction and a metric scale
  // (*from_wheels then true).
  std::optional<Pose3> PredictPose(Time stamp, bool* from_wheels = nullptr) const;
  void RememberPose(Time stamp, const Pose3& world_camera);
  // The ICGM options for the motion prior of the current frame's prediction.
  IcgmOptions PriorOptions() const;
  // Median distance (px) between `points` projected with `predicted` and `pixels`, over the
  // correspondences flagged in `use`; nullopt with fewer than 10.
  std::optional<double> PredictionError(const Pose3& predicted,
                                        const std::vector<Eigen::Vector3d>& points,
                                        const std::vector<Eigen::Vector2d>& pixels,
                                        const std::vector<uint8_t>& use) const;

  MonoOptions options_;
  CameraIntrinsics intrinsics_;
  std::unique_ptr<FeatureExtractor> extractor_;
  DescriptorMatcher matcher_;
  WheelOdometryBuffer wheel_;
  std::optional<Pose3> base_to_camera_;
  bool undistort_ = false;

  MonoState state_ = MonoState::kInitializing;
  std::unique_ptr<Frame> reference_;  // initialization reference
  Pose3 reference_pose_ = Pose3::Identity();
  size_t frames_since_reference_ = 0;
  std::deque<std::shared_ptr<Keyframe>> window_;
  std::unordered_map<int, MapPoint> points_;
  int next_point_id_ = 0;
  size_t frames_since_keyframe_ = 0;
  size_t lost_frames_ = 0;
  bool scale_known_ = false;
  // scene_depth_band: the map's reference depth (map units), set at its initialization.
  std::optional<double> map_depth_;
  // Camera speed (map units per second) before the last loss, for the next map's scale.
  std::optional<double> carried_speed_;
  // relocalize_good_keyframe_points: the newest keyframe that carried that many map points
  // (none after a reset).
  std::shared_ptr<Keyframe> good_keyframe_;
  // ... the positions of its map points when it was made (points culled since stay usable).
  std::unordered_map<int, Eigen::Vector3d> good_points_;
  // relocalize_good_keyframe_points: the motion from good_keyframe_ to `frame` from the
  // essential matrix of their ICGM matches (its length from the keyframe's map points the two
  // views triangulate; none when too few), then Relocalize with that pose as the prediction;
  // `c` and `to_last` as there.
  PnpResult RelocalizeOnGoodKeyframe(const Frame& frame, Correspondences* c, Matches* to_last,
                                     MonoFrameResult* result) const;
  // reset_bridge_max_s: the last map's last two tracked poses, kept over a reset.
  std::deque<std::pair<Time, Pose3>> bridge_;
  // Last two poses (stamp, T_world_camera) for the constant-velocity prediction.
  std::deque<std::pair<Time, Pose3>> recent_;
  bool prediction_from_wheels_ = false;  // the current frame's prediction (ICGM prior Thr)
  // Median pixel error of the constant-velocity prediction on the last tracked frame
  // (prior_from_prediction_error); none after an initialization.
  std::optional<double> prediction_error_px_;
  std::optional<Pose3> last_pose_;  // last pose, kept across a loss
  // relocalize_while_initializing: window_ and points_ hold the map lost at the last reset.
  bool kept_map_ = false;
  // The last tracked frame and its pose (new_point_confirm_px); none after a reset or
  // an initialization.
  std::unique_ptr<Frame> previous_frame_;
  // track_icgm_baseline_frames: the last frames given to tracking (at most that many back),
  // with their tracked pose.
  std::deque<std::pair<std::unique_ptr<Frame>, std::optional<Pose3>>> baseline_frames_;
  Pose3 previous_world_camera_ = Pose3::Identity();
  // dynamic_mask_radius_px: pixels of rejected or off-pose matches to map points in the
  // current and the previous tracked frame.
  std::vector<Eigen::Vector2d> moving_pixels_, previous_moving_pixels_;
  size_t frame_count_ = 0;
  size_t num_keyframes_ = 0;
  size_t num_resets_ = 0;
};

}  // namespace icgm
