// A motion hypothesis from the local map (rgbd_frontend.h, frontend.map_hypothesis_keyframes).
//
// The current frame is located among the verified-static points of the last keyframes (the
// local map of local_map.h, in the odom frame) without a start pose: every usable current
// keypoint with depth is matched to the map by descriptor alone (nearest against second
// nearest, ratio test), and RANSAC + Horn (ransac_horn.h) finds the rigid motion that the most
// of those 3-D pairs agree with, judged by symmetric reprojection in a fixed viewing frame.
// The frame pair's registration chooses between a pan and a sideways slide on what two frames
// share; the map holds the room as seen from several keyframes, with the walkers' features
// left out where they were found, so its consistent set is the room's more often.
//
// The same correspondences give each candidate pose its map support: the number of matched
// map points that reproject onto their keypoints (and agree in depth) at that pose.
#pragma once

#include <cstddef>
#include <cstdint>
#include <map>
#include <memory>
#include <utility>
#include <vector>

#include <Eigen/Core>
#include <opencv2/core.hpp>

#include "core/common/camera.h"
#include "core/common/pose.h"
#include "core/common/status.h"
#include "core/odometry/local_map.h"
#include "core/registration/depth_points.h"

namespace icgm {

struct MapHypothesisOptions {
  // Keyframes whose points form the map (the most recent ones, and the frame's reference);
  // 0: off.
  int keyframes = 0;
  // Descriptor match: nearest map point within this distance (Hamming for binary descriptors,
  // else L2) and nearer than ratio times the second nearest.
  double max_descriptor_distance = 64.0;
  double ratio = 0.8;
  // Map points this close to the nearest are taken for the same room point (seen by another
  // keyframe), not as the second nearest of the ratio test.
  double same_point_m = 0.1;
  // > 0: a keypoint is matched only to map points that appear within this many pixels of it
  // (each axis) in the viewing frame; 0: the whole map.
  double window_px = 0.0;
  // RANSAC inliers and map support: symmetric reprojection within this many pixels (times the
  // keypoint's sigma), depths within depth_abs_m + depth_rel_per_m * z^2.
  double reprojection_px = 2.0;
  double depth_abs_m = 0.03;
  double depth_rel_per_m = 0.015;
  int min_inliers = 20;  // fewer: no hypothesis
  int max_iterations = 300;
  uint64_t rng_seed = 7;
  // > 0: each hypothesis's map support (over the best support among the frame's hypotheses)
  // joins the depth and edge evidence with this weight (0: the map only adds a hypothesis).
  double evidence_weight = 0.0;
  // Persistence (> 0 keyframes): a map point counts only when the keyframes of the frontend's
  // window saw a point of like descriptor (within max_descriptor_distance) within
  // persistence_radius_m of it in at least persistence_keyframes keyframes (its own included)
  // spanning at least persistence_span_s. People move within seconds, the room does not.
  int persistence_keyframes = 0;
  double persistence_span_s = 0.0;
  double persistence_radius_m = 0.05;
};

// One keyframe's map points and its capture time.
struct TimedMapPoints {
  LocalMapPoints points;
  double stamp_s = 0.0;
};

// The points of `recent` that the `observers` (keyframes, `recent`'s own among them or not)
// saw persistently (persistence_* above), merged into one map. With persistence_keyframes <= 0
// every point of `recent` is kept.
LocalMapPoints PersistentPoints(const std::vector<TimedMapPoints>& recent,
                                const std::vector<TimedMapPoints>& observers,
                                const MapHypothesisOptions& options);

// PersistentPoints over a sliding window of keyframes, with what depends on the keyframes alone
// kept between calls: each observer's neighbour cells, which points of one keyframe another
// saw, and the merged map. Each keyframe comes with an id that must change whenever its points
// do; only pairs with a new id are compared again. The result equals PersistentPoints' for the
// same points.
class PersistenceCache {
 public:
  struct Keyframe {
    uint64_t id = 0;
    std::shared_ptr<const TimedMapPoints> points;
  };
  PersistenceCache();
  ~PersistenceCache();
  LocalMapPoints Points(const std::vector<Keyframe>& recent, const std::vector<Keyframe>& observers,
                        const MapHypothesisOptions& options);

 private:
  struct Cells;
  std::map<uint64_t, std::unique_ptr<Cells>> cells_;  // by observer id
  // Which points of keyframe `first` keyframe `second` saw (empty: it cannot judge them).
  std::map<std::pair<uint64_t, uint64_t>, std::vector<uint8_t>> seen_;
  // The last call's keyframes, options and map.
  std::vector<uint64_t> recent_ids_, observer_ids_;
  MapHypothesisOptions options_;
  bool has_map_ = false;
  LocalMapPoints map_;
};

// Current keypoints matched to map points, with the keypoint's camera-frame point.
struct MapCorrespondences {
  std::vector<int> keypoint;                   // index into the current keypoints
  std::vector<Eigen::Vector3d> camera_points;  // current camera frame (metres)
  std::vector<Eigen::Vector3d> odom_points;    // the matched map point (odom frame)
  std::vector<Eigen::Vector2d> pixels;         // the current keypoint's position
  std::vector<double> sigma_px;                // the current keypoint's pixel sigma
  size_t size() const { return keypoint.size(); }
};

struct MapHypothesis {
  Status status = Status::Ok();
  Pose3 odom_camera = Pose3::Identity();  // T_odom_camera of the current frame (when ok)
  MapCorrespondences correspondences;     // every descriptor match (also when not ok)
  size_t inliers = 0;
};

// Matches the current frame (keypoints, descriptors, one pixel sigma per keypoint, `usable`
// flags or empty for all, CV_32FC1 depth in metres with `depth` validity rules) to `map` by
// descriptor and locates it by RANSAC. `viewing_frame` (T_odom_camera of a nearby frame, e.g.
// the previous one) only fixes where the map points are projected for the reprojection test;
// the result does not start from it.
MapHypothesis LocateInLocalMap(const LocalMapPoints& map,
                               const std::vector<cv::KeyPoint>& keypoints,
                               const cv::Mat& descriptors,
                               const std::vector<double>& pixel_sigma_px,
                               const std::vector<uint8_t>& usable, const cv::Mat& depth_m,
                               const DepthPointOptions& depth, const Pose3& viewing_frame,
                               const CameraIntrinsics& intrinsics,
                               const MapHypothesisOptions& options);

// The correspondences that `odom_camera` explains: map point projected within
// reprojection_px x sigma of its keypoint, in front of the camera, depth agreeing.
size_t MapSupport(const MapCorrespondences& correspondences, const Pose3& odom_camera,
                  const CameraIntrinsics& intrinsics, const MapHypothesisOptions& options);

}  // namespace icgm
