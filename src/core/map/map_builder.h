// Incremental hybrid-map construction (thesis 6.1.1.2, Fig. 6.2): for each new metric model
//   L_Current = L_(n-1) (+) R_n (eq. 6.1)  ->  dictionary query  ->  loop-closure detection
//   -> register the model  ->  on a loop closure, loop links and the eq. 6.4 correction with
//   alpha_mapping (mapping) or alpha_localization (= 1, localization / navigation, 6.1.2)
//   -> add the model's words to the dictionary.
// With loop_closure.correction = pose_graph the eq. 6.4 step is replaced by a full pose-graph
// optimization over all odometry and loop links (PoseGraphOptimizer); in localization mode only
// the current loop's keyframes move (earlier loops are the reference, as in 6.1.2).
// This is the single entry point for the map-building nodelet and the offline runner.
#pragma once

#include <string>
#include <vector>

#include "core/common/status.h"
#include "core/map/hybrid_map.h"
#include "core/map/loop_closure.h"
#include "core/map/pose_graph_optimizer.h"
#include "core/map/visual_dictionary.h"

namespace icgm {

// Information of a visual odometry link (`map.visual_information`): the fixed sigmas, or the
// front end's registration covariance (with floor sigmas).
enum class VisualInformation { kFixed, kRegistration };

template <>
struct EnumNames<VisualInformation> {
  static constexpr EnumName<VisualInformation> kNames[] = {
      {VisualInformation::kFixed, "fixed"}, {VisualInformation::kRegistration, "registration"}};
};

struct MapOptions {
  // Information of odometry links when the caller gives none: isotropic sigmas per source.
  double visual_sigma_m = 0.02;
  double visual_sigma_rad = 0.01;
  double wheel_sigma_m = 0.05;
  double wheel_sigma_rad = 0.03;
  int min_keyframe_features = 10;  // fewer ICGM features: added, but not used for loop closure
  // Information of a visual odometry link when the caller passes the front end's registration
  // covariance (OdometryInformation): fixed ignores it (the sigmas above), registration
  // inverts it after adding the floor sigmas below (a registration's covariance does not
  // include its bias, e.g. from a biased depth).
  VisualInformation visual_information = VisualInformation::kRegistration;
  double registration_floor_sigma_m = 0.005;
  double registration_floor_sigma_rad = 0.002;
  // Wheel-odometry links beside visual odometry links (LinkType::kWheelOdometry), weighed by
  // the pose-graph back end: per axis sigma = floor + per_m * length of the step. The wheels
  // drift slowly (a scale error, a heading bias per metre), so over one keyframe step they can
  // pin heading and tilt better than a registration does.
  bool wheel_links = true;
  double wheel_link_floor_sigma_m = 0.005;
  double wheel_link_sigma_m_per_m = 0.03;
  double wheel_link_floor_sigma_rad = 0.001;
  double wheel_link_sigma_rad_per_m = 0.005;
  // Keep each keyframe's depth and colour images, subsampled by depth_image_downsample
  // (keyframe_images.h; about 100 kB per keyframe at 4 from 640x480), for dense map products
  // (icgm_map_export: coloured cloud, occupancy grid) and their check for walkers.
  bool store_depth_images = true;
  int depth_image_downsample = 4;
};

struct MapBuilderOptions {
  DictionaryOptions dictionary;
  LoopClosureOptions loop_closure;
  MapOptions map;
  PoseGraphOptions pose_graph;  // used when loop_closure.correction is pose_graph
};

enum class MapMode { kMapping, kLocalization };

template <>
struct EnumNames<MapMode> {
  static constexpr EnumName<MapMode> kNames[] = {{MapMode::kMapping, "mapping"},
                                                 {MapMode::kLocalization, "localization"}};
};

struct KeyframeUpdate {
  int keyframe_id = -1;
  Pose3 pose_before_correction = Pose3::Identity();  // L_Current from the own loop
  Pose3 pose = Pose3::Identity();                    // L_n after any correction
  bool loop_closed = false;
  LoopClosureResult loop;
  // Pose-graph correction only: the optimizer's status and summary. When it fails, eq. 6.4 is
  // applied instead so the loop closure still corrects the map.
  Status pose_graph_status = Status::Error("pose graph not run");
  PoseGraphSummary pose_graph;
};

class MapBuilder {
 public:
  explicit MapBuilder(const MapBuilderOptions& options);

  // Adopts a loaded (or merged) map and rebuilds its dictionary; new keyframes extend its last
  // session unless StartSession is called.
  Status Reset(HybridMap map);
  void SetMode(MapMode mode) { mode_ = mode; }
  MapMode mode() const { return mode_; }
  int StartSession(const std::string& name) { return map_.StartSession(name); }
  int StartLoop() { return map_.StartLoop(); }

  // Adds one metric model. `keyframe` needs stamp, ICGM features (keypoints, descriptors),
  // points_m, relative_pose R_n and relative_source; ids and global pose are assigned here.
  // `odometry_information` (optional) weighs the odometry link; default OdometryInformation
  // without a registration covariance (MapOptions).
  // `wheel_motion` (optional): the camera's motion since the previous keyframe of the session
  // as the wheels measured it (this keyframe in the previous one's camera frame); with
  // map.wheel_links and a visual R_n it becomes a wheel-odometry link, before any loop closure.
  // A failed loop closure is not an error (update->loop.status says why).
  Status AddKeyframe(Keyframe keyframe, const RegisterFn& register_fn, KeyframeUpdate* update,
                     const Mat6* odometry_information = nullptr,
                     const Pose3* wheel_motion = nullptr);

  // Localization against the map without writing to it: the loop-closure detection of
  // AddKeyframe (dictionary candidates of every loop, registration, guard, eq. 6.2) for a
  // `query` that is not added (query.session_id -1: no model of the map is excluded as recent).
  // query.global_pose is the predicted pose; `path_since_fix_m` scales the guard's uncertainty
  // (infinity: no prediction, the guard is open, as for a global relocalization). Only models
  // with id < `max_id` are candidates (the learned map; later ones are the robot's own). On
  // success result.loop_closure_pose is the query's pose in the map.
  LoopClosureResult Relocalize(const Keyframe& query, const RegisterFn& register_fn,
                               double path_since_fix_m, int max_id) const;

  // Information of a wheel-odometry link measuring `wheel_motion` (map.wheel_link_*).
  Mat6 WheelLinkInformation(const Pose3& wheel_motion) const;

  // Information of the odometry link of a keyframe whose relative pose came from `source`;
  // `registration_covariance` (optional, pose_refinement.h convention) is the covariance of the
  // front end's registration behind a visual relative pose, used per map.visual_information.
  // `wheel_motion` (optional, as in AddKeyframe): a step the wheels placed then gets
  // WheelLinkInformation (with map.wheel_links) instead of the fixed map.wheel_sigma_*, which
  // are left for steps of unknown length (e.g. held by constant velocity).
  Mat6 OdometryInformation(RelativePoseSource source,
                           const Mat6* registration_covariance = nullptr,
                           const Pose3* wheel_motion = nullptr) const;

  // Replaces every keyframe's global pose (e.g. after a bundle adjustment of the whole map);
  // relative poses are recomputed, links and the dictionary are unchanged.
  Status SetGlobalPoses(const std::vector<Pose3>& poses) { return map_.SetGlobalPoses(poses); }
  const HybridMap& map() const { return map_; }
  const VisualDictionary& dictionary() const { return dictionary_; }
  const MapBuilderOptions& options() const { return options_; }

 private:
  Mat6 DefaultInformation(RelativePoseSource source) const;
  // Optimizes the whole graph after the loop closure at keyframe `id`; false: not applied.
  bool CorrectWithPoseGraph(int id, KeyframeUpdate* update);

  MapBuilderOptions options_;
  MapMode mode_ = MapMode::kMapping;
  HybridMap map_;
  VisualDictionary dictionary_;
  LoopClosureDetector detector_;
};

}  // namespace icgm
