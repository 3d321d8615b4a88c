#include "core/map/occupancy_grid_io.h"

#include <filesystem>
#include <fstream>
#include <vector>

namespace icgm {

Status WriteMapServerGrid(const OccupancyGrid& grid, const std::string& path,
                          std::string* pgm_out, std::string* yaml_out) {
  namespace fs = std::filesystem;
  if (grid.width <= 0 || grid.height <= 0) return Status::Error("the occupancy grid is empty");
  fs::path base(path);
  if (base.extension() == ".pgm" || base.extension() == ".yaml") base.replace_extension();
  const fs::path pgm = fs::path(base).concat(".pgm");
  const fs::path yaml = fs::path(base).concat(".yaml");
  std::vector<uint8_t> pixels(static_cast<size_t>(grid.width) * grid.height);
  for (int y = 0; y < grid.height; ++y) {
    const int row = grid.height - 1 - y;  // image top = highest y
    for (int x = 0; x < grid.width; ++x) {
      const int8_t v = grid.at(x, y);
      pixels[static_cast<size_t>(row) * grid.width + x] =
          v == OccupancyGrid::kUnknown ? 205 : (v >= 50 ? 0 : 254);
    }
  }
  {
    std::ofstream out(pgm, std::ios::binary);
    out << "P5\n# icgm_slam occupancy grid\n" << grid.width << " " << grid.height << "\n255\n";
    out.write(reinterpret_cast<const char*>(pixels.data()),
              static_cast<std::streamsize>(pixels.size()));
    if (!out) return Status::Error("cannot write '" + pgm.string() + "'");
  }
  {
    std::ofstream out(yaml);
    out.precision(9);
    out << "image: " << pgm.filename().string() << "\n"
        << "resolution: " << grid.resolution_m << "\n"
        << "origin: [" << grid.origin_m.x() << ", " << grid.origin_m.y() << ", 0.0]\n"
        << "negate: 0\noccupied_thresh: 0.65\nfree_thresh: 0.196\n";
    if (!out) return Status::Error("cannot write '" + yaml.string() + "'");
  }
  if (pgm_out) *pgm_out = pgm.string();
  if (yaml_out) *yaml_out = yaml.string();
  return Status::Ok();
}

}  // namespace icgm
