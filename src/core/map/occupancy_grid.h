// A 2-D occupancy grid of the map (the layout of nav_msgs/OccupancyGrid and of map_server's
// files): cell (x, y) covers [origin + x * res, origin + (x + 1) * res) in the map frame's x and
// y, row-major from the lowest y; -1 unknown, 0 free, 100 occupied.
//
// Built from map points (map_points.h) and the poses of the keyframes that saw them, in a map
// frame whose z axis points up from the floor (z = 0), as for a wheeled robot whose odometry
// frame starts at base_link on the floor. A point between min_height_m and max_height_m is an
// obstacle hit in its cell; every ray from its keyframe's camera to a point (up to max_range_m)
// passes the cells it crosses while its height lies in the band: those are free evidence. Points
// above or below the band (floor, ceiling) so still clear the space the ray crossed inside it.
// A cell is occupied with at least min_hits hits making up at least min_occupied_ratio of its
// evidence (hits + passes), free with any other evidence, unknown without any.
#pragma once

#include <cstdint>
#include <vector>

#include <Eigen/Core>

#include "core/map/hybrid_map.h"
#include "core/map/map_points.h"

namespace icgm {

class OptionReader;

struct OccupancyGrid {
  static constexpr int8_t kUnknown = -1;
  static constexpr int8_t kFree = 0;
  static constexpr int8_t kOccupied = 100;

  double resolution_m = 0.05;
  Eigen::Vector2d origin_m = Eigen::Vector2d::Zero();  // corner of cell (0, 0), map frame
  int width = 0;
  int height = 0;
  std::vector<int8_t> data;  // width * height, row y = data[y * width ...]

  int8_t at(int x, int y) const { return data[static_cast<size_t>(y) * width + x]; }
  // The cell of map point (x, y); false outside the grid.
  bool CellOf(const Eigen::Vector2d& xy_m, int* x, int* y) const;
  size_t Count(int8_t value) const;
};

struct OccupancyGridOptions {
  double resolution_m = 0.05;
  double min_height_m = 0.1;  // obstacle band above the floor (z = 0 of the map frame)
  double max_height_m = 1.8;
  double max_range_m = 5.0;   // rays and hits beyond this distance from the camera are ignored
  int min_hits = 2;
  double min_occupied_ratio = 0.2;
  double margin_m = 0.5;      // around the observed area
};

// Fills `options` from an `occupancy_grid:` section; throws LoadError on bad values.
void ReadOptions(const OptionReader& reader, OccupancyGridOptions* options);

// `camera_positions_m[id]`: the camera centre of keyframe id in the map frame; each point's
// keyframe_id indexes it.
OccupancyGrid BuildOccupancyGrid(const std::vector<Eigen::Vector3d>& camera_positions_m,
                                 const std::vector<MapPoint>& points,
                                 const OccupancyGridOptions& options);
// The same with the camera centres of `map`'s keyframes.
OccupancyGrid BuildOccupancyGrid(const HybridMap& map, const std::vector<MapPoint>& points,
                                 const OccupancyGridOptions& options);

// Whether a point lies in the obstacle band and within range of its camera: a hit.
bool IsGridHit(const Eigen::Vector3d& camera_m, const Eigen::Vector3f& point_m,
               const OccupancyGridOptions& options);

}  // namespace icgm
