// How much of the map products lies on people, against ground truth: each exported point knows
// its keyframe and full-image pixel (map_points.h); `on_person(keyframe_id, pixel)` tells whether
// a walker was the visible surface there (e.g. the simulator's dynamic mask, sim_people_truth.h).
//  - cloud: points before the voxel filter, and voxels (as pcl::VoxelGrid makes them, VoxelIndex)
//    counted on people when ANY of their points is;
//  - grid: occupied cells counted on people when ANY of the hits that landed in them is.
#pragma once

#include <cstddef>
#include <functional>
#include <vector>

#include <Eigen/Core>
#include <opencv2/core.hpp>

#include "core/map/map_points.h"
#include "core/map/occupancy_grid.h"

namespace icgm {

using PersonTruth = std::function<bool(int keyframe_id, const cv::Point2f& pixel)>;

struct PeopleShare {
  size_t points = 0, points_on_people = 0;
  size_t voxels = 0, voxels_on_people = 0;
  size_t occupied_cells = 0, occupied_cells_on_people = 0;
  static double Share(size_t part, size_t whole) { return whole ? double(part) / whole : 0.0; }
  double PointShare() const { return Share(points_on_people, points); }
  double VoxelShare() const { return Share(voxels_on_people, voxels); }
  double GridShare() const { return Share(occupied_cells_on_people, occupied_cells); }
};

// `points`: the exported (static) points before the voxel filter; `grid` built from them with
// `grid_options` and the keyframe camera centres `cameras_m`.
PeopleShare MeasurePeopleShare(const std::vector<MapPoint>& points, double voxel_m,
                               const OccupancyGrid& grid,
                               const std::vector<Eigen::Vector3d>& cameras_m,
                               const OccupancyGridOptions& grid_options,
                               const PersonTruth& on_person);

}  // namespace icgm
