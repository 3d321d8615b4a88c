// Options of the dense map products (config/map_export.yaml): `map_cloud:` (map_points.h),
// `static_points:` (static_points.h) and `occupancy_grid:` (occupancy_grid.h).
#pragma once

#include <string>

#include "core/common/option_reader.h"
#include "core/map/map_points.h"
#include "core/map/occupancy_grid.h"
#include "core/map/static_points.h"

namespace icgm {

struct MapExportOptions {
  MapCloudOptions cloud;
  StaticPointOptions static_points;
  OccupancyGridOptions grid;
};

// Root reader: the three sections; unknown keys in them or at the top level are a LoadError
// naming them.
void ReadOptions(const OptionReader& reader, MapExportOptions* options);
// Reads a file (throws LoadError).
MapExportOptions LoadMapExportOptions(const std::string& path);

}  // namespace icgm
