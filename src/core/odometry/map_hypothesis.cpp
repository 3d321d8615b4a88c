#include "core/odometry/map_hypothesis.h"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <unordered_map>

#include <opencv2/features2d.hpp>

#include "core/registration/ransac_horn.h"

namespace icgm {

MapHypothesis LocateInLocalMap(const LocalMapPoints& map,
                               const std::vector<cv::KeyPoint>& keypoints,
                               const cv::Mat& descriptors,
                               const std::vector<double>& pixel_sigma_px,
                               const std::vector<uint8_t>& usable, const cv::Mat& depth_m,
                               const DepthPointOptions& depth, const Pose3& viewing_frame,
                               const CameraIntrinsics& intrinsics,
                               const MapHypothesisOptions& options) {
  MapHypothesis result;
  if (map.size() < 3 || keypoints.empty() ||
      descriptors.rows != static_cast<int>(keypoints.size()) ||
      pixel_sigma_px.size() != keypoints.size() || descriptors.type() != map.descriptors.type() ||
      descriptors.cols != map.descriptors.cols || depth_m.empty()) {
    result.status = Status::Error("map hypothesis: no map points or no usable current features");
    return result;
  }
  std::vector<cv::Point2f> pixels;
  pixels.reserve(keypoints.size());
  for (const cv::KeyPoint& k : keypoints) pixels.push_back(k.pt);
  std::vector<Eigen::Vector3d> points;
  std::vector<uint8_t> lifted;
  KeypointsToPoints(pixels, depth_m, intrinsics, depth, &points, &lifted);
  const int norm = map.binary ? cv::NORM_HAMMING : cv::NORM_L2;
  // Map points in the viewing frame, and where they appear there (NaN behind the camera).
  const Pose3 view_odom = viewing_frame.inverse();
  std::vector<Eigen::Vector3d> viewed(map.size());
  std::vector<Eigen::Vector2d> viewed_px(map.size());
  for (size_t p = 0; p < map.size(); ++p) {
    viewed[p] = view_odom * map.odom_points[p];
    viewed_px[p] = viewed[p].z() > 0.1 ? intrinsics.Project(viewed[p])
                                       : Eigen::Vector2d::Constant(std::nan(""));
  }
  MapCorrespondences& c = result.correspondences;
  std::vector<Eigen::Vector3d> src, dst;  // the RANSAC's 3-D pairs (map point in view)
  ReprojectionInlierTest test;
  test.intrinsics = intrinsics;
  test.threshold_px = options.reprojection_px;
  test.depth_abs_m = options.depth_abs_m;
  test.depth_rel_per_m = options.depth_rel_per_m;
  // Nearest and second nearest map descriptor of every usable keypoint with depth.
  std::vector<int> queried;
  cv::Mat query;
  for (size_t i = 0; i < keypoints.size(); ++i) {
    if (!lifted[i] || (!usable.empty() && !usable[i])) continue;
    queried.push_back(static_cast<int>(i));
    query.push_back(descriptors.row(static_cast<int>(i)));
  }
  // The same room point is in the map once per keyframe that kept it: the ratio test compares
  // the nearest with the nearest map point elsewhere (further than same_point_m from it).
  // window_px > 0: only map points that appear within window_px of the keypoint in the
  // viewing frame are candidates.
  cv::Mat mask;
  if (options.window_px > 0.0 && !queried.empty()) {
    mask = cv::Mat::zeros(static_cast<int>(queried.size()), static_cast<int>(map.size()), CV_8U);
    for (size_t q = 0; q < queried.size(); ++q) {
      const cv::Point2f& u = keypoints[queried[q]].pt;
      uint8_t* row = mask.ptr<uint8_t>(static_cast<int>(q));
      for (size_t p = 0; p < map.size(); ++p) {
        const Eigen::Vector2d& v = viewed_px[p];
        row[p] = std::abs(v.x() - u.x) <= options.window_px &&
                 std::abs(v.y() - u.y) <= options.window_px;
      }
    }
  }
  std::vector<std::vector<cv::DMatch>> knn;
  if (!queried.empty()) {
    cv::BFMatcher(norm).knnMatch(query, map.descriptors, knn, std::max(2, options.keyframes + 2),
                                 mask);
  }
  for (size_t q = 0; q < knn.size(); ++q) {
    if (knn[q].empty()) continue;
    const size_t i = static_cast<size_t>(queried[knn[q][0].queryIdx]);
    const int best = knn[q][0].trainIdx;
    const double best_d = knn[q][0].distance;
    double other_d = INFINITY;
    for (size_t n = 1; n < knn[q].size(); ++n) {
      if ((map.odom_points[knn[q][n].trainIdx] - map.odom_points[best]).norm() >
          options.same_point_m) {
        other_d = knn[q][n].distance;
        break;
      }
    }
    if (best_d > options.max_descriptor_distance || best_d > options.ratio * other_d) continue;
    c.keypoint.push_back(static_cast<int>(i));
    c.camera_points.push_back(points[i]);
    c.odom_points.push_back(map.odom_points[best]);
    c.pixels.emplace_back(keypoints[i].pt.x, keypoints[i].pt.y);
    c.sigma_px.push_back(pixel_sigma_px[i]);
    if (viewed_px[best].allFinite()) {
      src.push_back(points[i]);
      dst.push_back(viewed[best]);
      test.src_px.push_back(c.pixels.back());
      test.dst_px.push_back(viewed_px[best]);
      test.sigma_px.push_back(pixel_sigma_px[i]);
    }
  }
  if (static_cast<int>(src.size()) < std::max(3, options.min_inliers)) {
    std::ostringstream s;
    s << "map hypothesis: " << src.size() << " map matches < " << options.min_inliers;
    result.status = Status::Error(s.str());
    return result;
  }
  RansacOptions ransac;
  ransac.inlier_threshold_m = options.depth_abs_m;
  ransac.max_iterations = options.max_iterations;
  ransac.min_inliers = options.min_inliers;
  ransac.rng_seed = options.rng_seed;
  const RansacResult r = RansacHorn(src, dst, ransac, &test);
  result.inliers = r.inliers.size();
  if (!r.status.ok()) {
    result.status = Status::Error("map hypothesis: " + r.status.reason());
    return result;
  }
  result.odom_camera = viewing_frame * r.transform;
  return result;
}

// Named (not anonymous) because PersistenceCache::Cells, declared in the header, holds one.
namespace map_hypothesis_internal {

// Points of one keyframe hashed by cell of `cell_m` for neighbour look-ups.
class PointCells {
 public:
  PointCells(const LocalMapPoints& points, double cell_m) : points_(points), cell_m_(cell_m) {
    for (size_t i = 0; i < points.size(); ++i)
      cells_[Key(Cell(points.odom_points[i]))].push_back(i);
  }
  // Whether a point within radius_m of `p` has a descriptor within max_distance of `d`.
  bool Sees(const Eigen::Vector3d& p, const cv::Mat& d, int norm, double radius_m,
            double max_distance) const {
    const Eigen::Vector3i c = Cell(p);
    for (int dx = -1; dx <= 1; ++dx) {
      for (int dy = -1; dy <= 1; ++dy) {
        for (int dz = -1; dz <= 1; ++dz) {
          const auto it = cells_.find(Key(c + Eigen::Vector3i(dx, dy, dz)));
          if (it == cells_.end()) continue;
          for (const size_t i : it->second) {
            if ((points_.odom_points[i] - p).norm() > radius_m) continue;
            if (cv::norm(d, points_.descriptors.row(static_cast<int>(i)), norm) <= max_distance) {
              return true;
            }
          }
        }
      }
    }
    return false;
  }

 private:
  Eigen::Vector3i Cell(const Eigen::Vector3d& p) const {
    return (p / cell_m_).array().floor().cast<int>();
  }
  static int64_t Key(const Eigen::Vector3i& c) {
    return (static_cast<int64_t>(c.x() & 0x1FFFFF) << 42) |
           (static_cast<int64_t>(c.y() & 0x1FFFFF) << 21) | static_cast<int64_t>(c.z() & 0x1FFFFF);
  }
  const LocalMapPoints& points_;
  double cell_m_;
  std::unordered_map<int64_t, std::vector<size_t>> cells_;
};

}  // namespace map_hypothesis_internal

using map_hypothesis_internal::PointCells;

namespace {

// The persistence radius (at least 1 mm): the search radius and the neighbour cells' size.
double CellSize(const MapHypothesisOptions& options) {
  return std::max(1e-3, options.persistence_radius_m);
}

// Which points of `kf` `observer` saw (a point within the radius with a like descriptor);
// empty when the observer cannot judge them (same capture time, other descriptors).
std::vector<uint8_t> SeenBy(const TimedMapPoints& kf, const TimedMapPoints& observer,
                            const PointCells& cells, const MapHypothesisOptions& options) {
  if (observer.stamp_s == kf.stamp_s || observer.points.binary != kf.points.binary ||
      observer.points.descriptors.type() != kf.points.descriptors.type() ||
      observer.points.descriptors.cols != kf.points.descriptors.cols) {
    return {};
  }
  const int norm = kf.points.binary ? cv::NORM_HAMMING : cv::NORM_L2;
  std::vector<uint8_t> seen(kf.points.size(), 0);
  for (size_t i = 0; i < kf.points.size(); ++i) {
    seen[i] = cells.Sees(kf.points.odom_points[i], kf.points.descriptors.row(static_cast<int>(i)),
                         norm, CellSize(options), options.max_descriptor_distance);
  }
  return seen;
}

// Appends to `map` the points of `kf` that persisted: with the observers' stamps and SeenBy
// results, in at least persistence_keyframes keyframes (its own included) spanning at least
// persistence_span_s; every point with persistence_keyframes <= 0.
void AppendPersistent(const TimedMapPoints& kf,
                      const std::vector<std::pair<double, const std::vector<uint8_t>*>>& seen_by,
                      const MapHypothesisOptions& options, LocalMapPoints* map) {
  std::vector<uint8_t> keep(kf.points.size(), 1);
  for (size_t i = 0; options.persistence_keyframes > 0 && i < kf.points.size(); ++i) {
    int seen = 1;
    double first = kf.stamp_s, last = kf.stamp_s;
    for (const auto& [stamp_s, mask] : seen_by) {
      if (mask->empty() || !(*mask)[i]) continue;
      ++seen;
      first = std::min(first, stamp_s);
      last = std::max(last, stamp_s);
    }
    keep[i] = seen >= options.persistence_keyframes && last - first >= options.persistence_span_s;
  }
  if (map->descriptors.empty()) map->binary = kf.points.binary;
  for (size_t i = 0; i < kf.points.size(); ++i) {
    if (!keep[i] || kf.points.binary != map->binary) continue;
    map->odom_points.push_back(kf.points.odom_points[i]);
    map->descriptors.push_back(kf.points.descriptors.row(static_cast<int>(i)));
  }
}

}  // namespace

LocalMapPoints PersistentPoints(const std::vector<TimedMapPoints>& recent,
                                const std::vector<TimedMapPoints>& observers,
                                const MapHypothesisOptions& options) {
  LocalMapPoints map;
  std::vector<PointCells> cells;
  if (options.persistence_keyframes > 0) {
    cells.reserve(observers.size());
    for (const TimedMapPoints& o : observers) cells.emplace_back(o.points, CellSize(options));
  }
  for (const TimedMapPoints& kf : recent) {
    std::vector<std::vector<uint8_t>> seen(cells.size());
    std::vector<std::pair<double, const std::vector<uint8_t>*>> seen_by;
    for (size_t o = 0; o < cells.size(); ++o) {
      if (&observers[o].points == &kf.points) continue;
      seen[o] = SeenBy(kf, observers[o], cells[o], options);
      seen_by.emplace_back(observers[o].stamp_s, &seen[o]);
    }
    AppendPersistent(kf, seen_by, options, &map);
  }
  return map;
}

struct PersistenceCache::Cells {
  Cells(std::shared_ptr<const TimedMapPoints> p, double cell_m)
      : points(std::move(p)), cells(points->points, cell_m) {}
  std::shared_ptr<const TimedMapPoints> points;  // what `cells` refers to
  map_hypothesis_internal::PointCells cells;
};

PersistenceCache::PersistenceCache() = default;
PersistenceCache::~PersistenceCache() = default;

LocalMapPoints PersistenceCache::Points(const std::vector<Keyframe>& recent,
                                        const std::vector<Keyframe>& observers,
                                        const MapHypothesisOptions& options) {
  if (options.persistence_keyframes != options_.persistence_keyframes ||
      options.persistence_span_s != options_.persistence_span_s ||
      options.persistence_radius_m != options_.persistence_radius_m ||
      options.max_descriptor_distance != options_.max_descriptor_distance) {
    cells_.clear();
    seen_.clear();
    has_map_ = false;
    options_ = options;
  }
  std::vector<uint64_t> recent_ids, observer_ids;
  for (const Keyframe& k : recent) recent_ids.push_back(k.id);
  if (options.persistence_keyframes > 0) {
    for (const Keyframe& k : observers) observer_ids.push_back(k.id);
  }
  if (has_map_ && recent_ids == recent_ids_ && observer_ids == observer_ids_) return map_;
  std::map<uint64_t, std::unique_ptr<Cells>> cells;
  std::map<std::pair<uint64_t, uint64_t>, std::vector<uint8_t>> seen;
  for (size_t o = 0; o < observer_ids.size(); ++o) {
    auto it = cells_.find(observers[o].id);
    cells[observers[o].id] = it != cells_.end()
                                 ? std::move(it->second)
                                 : std::make_unique<Cells>(observers[o].points, CellSize(options));
    if (it != cells_.end()) cells_.erase(it);
  }
  LocalMapPoints map;
  for (const Keyframe& kf : recent) {
    std::vector<std::pair<double, const std::vector<uint8_t>*>> seen_by;
    for (size_t o = 0; o < observer_ids.size(); ++o) {
      if (observers[o].id == kf.id) continue;
      const std::pair<uint64_t, uint64_t> key(kf.id, observers[o].id);
      auto it = seen.find(key);
      if (it == seen.end()) {
        auto kept = seen_.find(key);
        it = seen.emplace(key, kept != seen_.end()
                                   ? std::move(kept->second)
                                   : SeenBy(*kf.points, *observers[o].points,
                                            cells.at(observers[o].id)->cells, options))
                 .first;
      }
      seen_by.emplace_back(observers[o].points->stamp_s, &it->second);
    }
    AppendPersistent(*kf.points, seen_by, options, &map);
  }
  // Only what this window uses is kept.
  cells_ = std::move(cells);
  seen_ = std::move(seen);
  recent_ids_ = std::move(recent_ids);
  observer_ids_ = std::move(observer_ids);
  map_ = map;
  has_map_ = true;
  return map;
}

size_t MapSupport(const MapCorrespondences& correspondences, const Pose3& odom_camera,
                  const CameraIntrinsics& intrinsics, const MapHypothesisOptions& options) {
  const Pose3 camera_odom = odom_camera.inverse();
  size_t support = 0;
  for (size_t k = 0; k < correspondences.size(); ++k) {
    const Eigen::Vector3d p = camera_odom * correspondences.odom_points[k];
    if (p.z() < 0.1) continue;
    const double z = correspondences.camera_points[k].z();
    if (std::abs(p.z() - z) > options.depth_abs_m + options.depth_rel_per_m * z * z) continue;
    const double tolerance_px = options.reprojection_px * correspondences.sigma_px[k];
    if ((intrinsics.Project(p) - correspondences.pixels[k]).norm() <= tolerance_px) ++support;
  }
  return support;
}

}  // namespace icgm
