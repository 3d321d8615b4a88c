#include "core/map_export/people_share.h"

#include <map>
#include <tuple>

#include "core/map_export/cloud_export.h"

namespace icgm {

PeopleShare MeasurePeopleShare(const std::vector<MapPoint>& points, double voxel_m,
                               const OccupancyGrid& grid,
                               const std::vector<Eigen::Vector3d>& cameras_m,
                               const OccupancyGridOptions& grid_options,
                               const PersonTruth& on_person) {
  PeopleShare share;
  std::map<std::tuple<int, int, int>, bool> voxels;
  std::vector<uint8_t> cell_people(grid.data.size(), 0);
  for (const MapPoint& p : points) {
    const bool person = on_person(p.keyframe_id, p.pixel);
    ++share.points;
    if (person) ++share.points_on_people;
    const Eigen::Vector3i v = VoxelIndex(p.position_m, voxel_m);
    bool& voxel = voxels[{v.x(), v.y(), v.z()}];
    voxel = voxel || person;
    if (!person || p.keyframe_id < 0 || p.keyframe_id >= static_cast<int>(cameras_m.size())) {
      continue;
    }
    if (!IsGridHit(cameras_m[p.keyframe_id], p.position_m, grid_options)) continue;
    int x = 0, y = 0;
    if (grid.CellOf(p.position_m.head<2>().cast<double>(), &x, &y)) {
      cell_people[static_cast<size_t>(y) * grid.width + x] = 1;
    }
  }
  share.voxels = voxels.size();
  for (const auto& [key, person] : voxels) share.voxels_on_people += person ? 1 : 0;
  for (size_t i = 0; i < grid.data.size(); ++i) {
    if (grid.data[i] != OccupancyGrid::kOccupied) continue;
    ++share.occupied_cells;
    share.occupied_cells_on_people += cell_people[i];
  }
  return share;
}

}  // namespace icgm
