// The people-free products of a learned map, as icgm_map_export writes them and the map builder
// publishes them for rviz: the map's points (map_points.h) checked against the other keyframes
// (static_points.h), the occupancy grid of the verified static points (occupancy_grid.h) and
// the static points voxel filtered (cloud_export.h: one coloured point per voxel). One sequence
// serves both users, so the tool's files and the nodelet's topics are the same products.
#pragma once

#include <cstddef>
#include <functional>
#include <vector>

#include "core/common/status.h"
#include "core/map/hybrid_map.h"
#include "core/map/map_export_options.h"
#include "core/map/map_points.h"
#include "core/map/occupancy_grid.h"
#include "core/map/static_points.h"

namespace icgm {

struct MapProducts {
  std::vector<MapPoint> cloud;  // static points, one per voxel of options.cloud.voxel_m
  OccupancyGrid grid;           // from the static points before the voxel filter
  StaticPointStats stats;
  // Filled only when asked for (keep_points): every gathered point and the static ones before
  // the voxel filter (people-share measurements compare the two).
  std::vector<MapPoint> points;
  std::vector<MapPoint> static_points;
};

// Called with (keyframes checked, keyframes) during the static check, the long part.
using MapProductsProgress = std::function<void(size_t, size_t)>;

// Gathers the map's points, keeps the verified static ones, builds the grid from them and voxel
// filters them. Fails on a map without keyframes or without any point.
Status BuildMapProducts(const HybridMap& map, const MapExportOptions& options,
                        MapProducts* products, const MapProductsProgress& progress = nullptr,
                        bool keep_points = false);

}  // namespace icgm
