// The occupancy grid in map_server's format: a binary PGM (P5) image, top row = highest y, with
// occupied 0 (black), free 254 (white) and unknown 205 (grey), and a YAML file naming the image
// with its resolution, origin (the lower-left cell's corner, yaw 0) and map_server's thresholds
// (negate 0, occupied_thresh 0.65, free_thresh 0.196), which read the three values back exactly.
#pragma once

#include <string>

#include "core/common/status.h"
#include "core/map/occupancy_grid.h"

namespace icgm {

// `path` names the pair: "out", "out.pgm" or "out.yaml" all write out.pgm and out.yaml. The
// YAML refers to the image by its file name (map_server resolves it beside the YAML).
Status WriteMapServerGrid(const OccupancyGrid& grid, const std::string& path,
                          std::string* pgm_path = nullptr, std::string* yaml_path = nullptr);

}  // namespace icgm
