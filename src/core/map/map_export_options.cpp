#include "core/map/map_export_options.h"

namespace icgm {

void ReadOptions(const OptionReader& reader, MapExportOptions* o) {
  const OptionReader cloud = reader.Section("map_cloud");
  const OptionReader static_points = reader.Section("static_points");
  const OptionReader grid = reader.Section("occupancy_grid");
  ReadOptions(cloud, &o->cloud);
  ReadOptions(static_points, &o->static_points);
  ReadOptions(grid, &o->grid);
  OptionReader::RejectUnknownKeys({&reader, &cloud, &static_points, &grid});
}

MapExportOptions LoadMapExportOptions(const std::string& path) {
  MapExportOptions options;
  ReadOptions(OptionReader::FromFile(path), &options);
  return options;
}

}  // namespace icgm
