// The hybrid SLAM system of thesis ch. 6.1 as one ROS-free object, shared by the offline
// runner (slam_runner.h, icgm_slam_map) and the map-building nodelet:
//   RGB-D frame -> RgbdFrontend (features, ICGM, 6-D registration, fusion with wheel odometry;
//   eq. 6.1 odometry) -> each new front-end keyframe becomes a metric model M_n
//   (keyframe_conversion.h) -> MapBuilder::AddKeyframe with KeyframeRegistration as RegisterFn
//   (loop closure with the 3 best models per earlier loop, eq. 6.2 pose-set optimization,
//   eq. 6.4 semi-consensus correction, alpha by mode).
// With map_features.source = tracker (the thesis profile, 6.1.3.1) a keyframe's map features
// are the double-directional ICGM set of its frame, which needs the next frame: the keyframe
// is held back and enters the map during the next ProcessFrame (that frame's result reports
// it), or at Flush (map_feature_tracking.h). AddKeyframe (keyframes made elsewhere) keeps the
// keyframe's flags: the live registration nodelet applies the same MapFeatureTracking first.
//
// Frames: map <- odom <- camera. T_odom_camera comes from the front end; the map corrects it
// through the latest map keyframe k of the current session:
//     T_map_odom = L_k * T_odom_camera(k)^-1,
// and a frame's map pose is the map pose of its keyframe composed with the odometry since it,
// T_map_camera = L_k * (T_odom_camera(k)^-1 * T_odom_camera(frame)). MapTrajectory() recomputes
// this for every frame with the current (corrected) keyframe poses.
//
// Sessions: a fresh system opens one session whose world frame is the odometry frame. After
// Load (replace or merge) the next keyframe opens a new session; its first keyframe is placed
// with the current T_map_odom, so the trajectory stays continuous (identity after a replace:
// the new recording starts where the loaded map's first session started, until a loop closure
// says otherwise).
//
// Localization (SetMode(kLocalization), thesis 6.1.2): the learned map is the reference and is
// never written. Each new keyframe is located in the map by MapBuilder::Relocalize (dictionary
// candidates of every learned loop, registration, guard); a verified location is a fix and sets
// T_map_odom. Options (localization.*, off by default, nearest_keyframe_localizer.h): once
// localized, the learned keyframes nearest to the predicted pose are registered first and the
// dictionary only when none verifies; a fix gate around the prediction; fixes fused with the
// prediction instead of replacing it. Until the first fix (after a Load, or with no initial
// pose) the guard is open: the robot relocalizes globally by place recognition. SetInitialPose
// (rviz's /initialpose) gives a fix by hand. Keyframes go nowhere, or with
// localization.keyframes = session to a separate session placed at the fixed poses. Saving
// follows SavePolicy: localization never writes the file the learned map came from, and
// autosaves to its own file.
//
// Robustness: bad images never throw (the front end flags them); a keyframe the map refuses is
// reported in SlamFrameResult::map_status and skipped (R_n of the next one chains from the
// last keyframe the map took); a failed Load leaves the map untouched; Save is atomic.
// Not thread-safe: call from one thread.
#pragma once

#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "core/common/camera.h"
#include "core/dataset/trajectory.h"
#include "core/map/map_builder.h"
#include "core/odometry/rgbd_frontend.h"
#include "core/slam/map_feature_tracking.h"
#include "core/slam/slam_options.h"

namespace icgm {

struct LoopClosureEvent {
  size_t frame_index = 0;
  Time stamp;
  int keyframe_id = -1;
  std::vector<int> candidate_ids;             // earlier models whose beta entered eq. 6.2
  int registrations = 0;                      // RegisterFn calls of this query
  Pose3 delta_pose_diff = Pose3::Identity();  // eq. 6.3
  Pose3 pose_before = Pose3::Identity();      // L_Current from the own loop
  Pose3 pose_after = Pose3::Identity();       // after eq. 6.4
};

struct SlamFrameResult {
  FrontendFrameResult frontend;
  Pose3 map_camera = Pose3::Identity();  // T_map_camera right after this frame
  bool keyframe = false;                 // the front end made a keyframe at this frame
  int keyframe_id = -1;                  // its map id (-1: none, or refused by the map)
  Status map_status = Status::Ok();      // why the map refused the keyframe
  KeyframeUpdate update;                 // of the keyframe (loop closure evidence)
  double map_ms = 0.0;                // MapBuilder::AddKeyframe: dictionary, loop closure, eq. 6.4
  double loop_registration_ms = 0.0;  // part of map_ms spent in RegisterFn
  int loop_registrations = 0;
};

// Parses "mapping" / "localization"; anything else is an error naming the choices.
Status ParseMapMode(const std::string& name, MapMode* mode);
const char* MapModeName(MapMode mode);

// Where the map is written (SlamSystem::Autosave, SaveMap). Mapping: map_path. Localization:
// localization_path (empty: no autosave), never the learned map's file.
struct SavePolicy {
  std::string map_path;
  std::string localization_path;
  int autosave_every_keyframes = 20;  // and on every loop closure; 0: only on loop closures
};

class SlamSystem {
 public:
  // Throws LoadError when the options ask for a back end this build lacks
  // (CheckBackEndAvailable: the pose graph without Ceres) or a dictionary that cannot hold the
  // front end's descriptors (CheckFeaturesFitDictionary).
  SlamSystem(const SlamOptions& options, const CameraIntrinsics& intrinsics);
  ~SlamSystem();

  // Wheel odometry T_odom_base samples, in time order (RgbdFrontend::AddWheelOdometry).
  Status AddWheelOdometry(Time stamp, const Pose3& odom_base);
  // One RGB-D frame (RgbdFrontend::ProcessFrame conventions). Never throws.
  SlamFrameResult ProcessFrame(Time stamp, const cv::Mat& bgr, const cv::Mat& depth_m,
                               std::optional<Time> depth_stamp = std::nullopt);
  // Distributed pipeline: a keyframe made outside this system's front end (the registration
  // nodelet's front end, placed with the fused odometry by the map-building nodelet) goes to
  // the map exactly as a front-end keyframe would. Stamps must increase. Never throws.
  SlamFrameResult AddKeyframe(const FrontendKeyframe& keyframe);
  // End of the frame sequence: a keyframe held back for its next frame (map_features.source =
  // tracker) enters the map, its features from the backward half of the window; nullopt when
  // none was held. SetMode, StartSession and Load flush too (the tracker restarts).
  std::optional<SlamFrameResult> Flush();

  // Mapping or localization (see the header comment). Entering localization keeps the current
  // T_map_odom as a fix when this system placed keyframes in the map since the last Load.
  void SetMode(MapMode mode);
  // By name (ParseMapMode); an unknown name is an error and the mode is unchanged.
  Status SetMode(const std::string& mode);
  MapMode mode() const;
  // Localization: the camera is at `map_camera` while the odometry says `odom_camera` (e.g. a
  // pose from rviz's /initialpose): a fix, T_map_odom = map_camera * odom_camera^-1; the guard
  // then admits relocalizations near it (loop_closure.sigma_*).
  void SetInitialPose(const Pose3& map_camera, const Pose3& odom_camera);
  // Localization has a fix (an initial pose or a verified relocalization).
  bool localized() const { return fix_.has_value(); }
  size_t relocalizations() const { return relocalizations_; }

  // Save policy (SavePolicy). Autosave: after a keyframe result, on a loop closure (or fix) or
  // every autosave_every_keyframes keyframes, to the mode's file; *written gets the path
  // (empty: nothing written, e.g. no path, nothing new, or localization without keyframes).
  void SetSavePolicy(SavePolicy policy) { save_policy_ = std::move(policy); }
  const SavePolicy& save_policy() const { return save_policy_; }
  Status Autosave(const SlamFrameResult& result, std::string* written);
  // Writes the map to `path` (empty: the mode's file); with `refine` in mapping mode, then
  // bundle-adjusts it (RefineMap) and writes it again, so a failed refinement loses nothing.
  // Localization never refines (the learned map is the reference) and refuses the learned
  // map's file. *detail (optional) describes what was done.
  Status SaveMap(const std::string& path, bool refine, std::string* detail = nullptr);
  // Starts a new learned loop (traversal) of the current session.
  void StartLoop();
  // The next keyframe opens a new session (a new recording), placed with the current
  // T_map_odom so the trajectory stays continuous.
  void StartSession();
  // Replaces the loop-closure registration (default: KeyframeRegistration with
  // options().keyframe_registration); an empty function restores the default.
  void SetRegisterFn(RegisterFn register_fn) { register_override_ = std::move(register_fn); }

  // Bundle adjustment of the whole map (map_refinement.h) with the loop-closure registration;
  // on success the refined keyframe poses replace the map's, and T_map_odom follows the latest
  // keyframe. On error the map is unchanged. Runs regardless of options().map_refinement.enabled
  // (that flag is for the callers: offline runs at the end, the nodelet before saving).
  Status RefineMap(MapRefinementSummary* summary = nullptr);

  // Writes the map (MapStore, atomic).
  Status Save(const std::string& path) const;
  // Reads a map. merge = false: it replaces the current map and the trajectory records;
  // merge = true: it is appended as further session(s) and the current map is kept. Either
  // way later keyframes go to a new session. On any error the current state is untouched.
  Status Load(const std::string& path, bool merge);
  // After a successful Load: a message for the user about the file's format (a version loaded
  // without checksums, map_store.h), else empty.
  const std::string& load_note() const { return load_note_; }

  const HybridMap& map() const;
  // T_map_odom (see the header comment); identity before the first keyframe.
  Pose3 MapFromOdom() const;
  // Every processed frame: T_map_camera with the current keyframe poses / T_odom_camera.
  Trajectory MapTrajectory() const;
  Trajectory OdomTrajectory() const;
  // Map keyframes added by this system since construction or the last Load: stamp and L_n.
  Trajectory KeyframeTrajectory() const;
  const std::vector<LoopClosureEvent>& loop_closures() const { return loop_closures_; }
  const RgbdFrontend& frontend() const { return *frontend_; }
  const SlamOptions& options() const { return options_; }

 private:
  // The loop-closure registration (or the override), adding its wall time to *ms and counting
  // its calls in *count.
  RegisterFn TimedRegistration(double* ms, int* count) const;
  // Appends the loop closure `result` made at `keyframe`, the keyframe ending at `pose_after`.
  void RecordLoopClosure(const FrontendKeyframe& keyframe, const SlamFrameResult& result,
                         const Pose3& pose_after);
  struct FrameRecord;
  struct MapKeyframeRef {
    int id = -1;
    Pose3 odom_camera = Pose3::Identity();
  };

  void AddToMap(const FrontendKeyframe& keyframe, SlamFrameResult* result);
  // A keyframe released by map_features_ enters the map (its own frame hangs from it).
  void AddHeldToMap(const FrontendKeyframe& keyframe, SlamFrameResult* result);
  // Localization mode's AddToMap: locate the keyframe, keep it per options().localization.
  void Localize(const FrontendKeyframe& keyframe, SlamFrameResult* result);
  Pose3 FramePose(const FrameRecord& record) const;

  SlamOptions options_;
  CameraIntrinsics intrinsics_;
  std::unique_ptr<RgbdFrontend> frontend_;
  std::unique_ptr<MapBuilder> builder_;
  std::unique_ptr<KeyframeRegistration> registration_;
  RegisterFn register_override_;

  KeyframePtr pending_;  // set by the front end's keyframe callback during ProcessFrame
  // Which features a keyframe brings into the map; holds it back one frame with
  // map_features.source = tracker (map_feature_tracking.h, also used by the live pipeline).
  std::unique_ptr<MapFeatureTracking> map_features_;
  std::optional<MapKeyframeRef> last_keyframe_;  // latest map keyframe of the current session
  std::optional<size_t> last_frontend_keyframe_;  // FrontendKeyframe::id of last_keyframe_
  std::vector<int> keyframe_ids_;                // map keyframes added by this system
  bool new_session_ = true;                      // the next keyframe opens a session
  Pose3 session_from_odom_ = Pose3::Identity();  // world of that session <- odom
  std::vector<FrameRecord> frames_;
  std::vector<LoopClosureEvent> loop_closures_;
  // Localization
  std::optional<Pose3> fix_;            // T_map_odom of the last fix
  OdometryFixFilter fix_filter_;        // localization.fuse_fixes: the fix's uncertainty
  double path_since_fix_m_ = 0.0;       // odometry path since then (the guard's uncertainty)
  std::optional<Pose3> last_localized_;  // T_odom_camera of the previous localization keyframe
  int learned_keyframes_ = 0;            // ids below this are the learned map (the reference)
  size_t relocalizations_ = 0;
  // Saving
  SavePolicy save_policy_;
  std::string loaded_path_;  // the learned map's file (Load)
  std::string load_note_;    // LoadMap's note on the last loaded file
  int keyframes_since_save_ = 0;
};

}  // namespace icgm
