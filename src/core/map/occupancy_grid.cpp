#include "core/map/occupancy_grid.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "core/common/option_reader.h"

namespace icgm {

bool OccupancyGrid::CellOf(const Eigen::Vector2d& xy_m, int* x, int* y) const {
  const double fx = std::floor((xy_m.x() - origin_m.x()) / resolution_m);
  const double fy = std::floor((xy_m.y() - origin_m.y()) / resolution_m);
  if (fx < 0 || fy < 0 || fx >= width || fy >= height) return false;
  *x = static_cast<int>(fx);
  *y = static_cast<int>(fy);
  return true;
}

size_t OccupancyGrid::Count(int8_t value) const {
  return static_cast<size_t>(std::count(data.begin(), data.end(), value));
}

void ReadOptions(const OptionReader& reader, OccupancyGridOptions* o) {
  reader.Read("resolution_m", &o->resolution_m, 0.005, 10.0);
  reader.Read("min_height_m", &o->min_height_m, -100.0, 100.0);
  reader.Read("max_height_m", &o->max_height_m, -100.0, 100.0);
  reader.Read("max_range_m", &o->max_range_m, 0.1, 1000.0);
  reader.Read("min_hits", &o->min_hits, 1, 1 << 20);
  reader.Read("min_occupied_ratio", &o->min_occupied_ratio, 0.0, 1.0);
  reader.Read("margin_m", &o->margin_m, 0.0, 100.0);
  if (!(o->max_height_m > o->min_height_m)) {
    throw LoadError(reader.path() + ".max_height_m: must be > min_height_m");
  }
}

bool IsGridHit(const Eigen::Vector3d& camera_m, const Eigen::Vector3f& point_m,
               const OccupancyGridOptions& options) {
  const Eigen::Vector3d p = point_m.cast<double>();
  return p.z() >= options.min_height_m && p.z() <= options.max_height_m &&
         (p - camera_m).norm() <= options.max_range_m;
}

OccupancyGrid BuildOccupancyGrid(const std::vector<Eigen::Vector3d>& cameras,
                                 const std::vector<MapPoint>& points,
                                 const OccupancyGridOptions& options) {
  OccupancyGrid grid;
  grid.resolution_m = options.resolution_m;
  const auto valid = [&](const MapPoint& p) {
    return p.keyframe_id >= 0 && p.keyframe_id < static_cast<int>(cameras.size());
  };
  // Bounds: the cameras and the hits, plus a margin.
  Eigen::Vector2d lo = Eigen::Vector2d::Constant(std::numeric_limits<double>::infinity());
  Eigen::Vector2d hi = -lo;
  for (const MapPoint& p : points) {
    if (!valid(p)) continue;
    const Eigen::Vector3d& c = cameras[p.keyframe_id];
    lo = lo.cwiseMin(c.head<2>());
    hi = hi.cwiseMax(c.head<2>());
    if (IsGridHit(c, p.position_m, options)) {
      lo = lo.cwiseMin(p.position_m.head<2>().cast<double>());
      hi = hi.cwiseMax(p.position_m.head<2>().cast<double>());
    }
  }
  if (!lo.allFinite()) return grid;
  lo -= Eigen::Vector2d::Constant(options.margin_m);
  hi += Eigen::Vector2d::Constant(options.margin_m);
  const double res = options.resolution_m;
  grid.origin_m = (lo / res).array().floor() * res;
  grid.width = static_cast<int>(std::ceil((hi.x() - grid.origin_m.x()) / res)) + 1;
  grid.height = static_cast<int>(std::ceil((hi.y() - grid.origin_m.y()) / res)) + 1;
  const size_t cells = static_cast<size_t>(grid.width) * grid.height;
  std::vector<uint32_t> hits(cells, 0), passes(cells, 0);

  for (const MapPoint& p : points) {
    if (!valid(p)) continue;
    const Eigen::Vector3d c = cameras[p.keyframe_id];
    Eigen::Vector3d end = p.position_m.cast<double>();
    const double length = (end - c).norm();
    const bool hit = IsGridHit(c, p.position_m, options);
    if (length > options.max_range_m) end = c + (end - c) * (options.max_range_m / length);
    int ex = -1, ey = -1;
    const bool end_in_grid = grid.CellOf(end.head<2>(), &ex, &ey);
    if (hit && end_in_grid) ++hits[static_cast<size_t>(ey) * grid.width + ex];
    // Walk the ray in steps of half a cell; count each crossed cell once, never the end cell.
    const double horizontal = (end - c).head<2>().norm();
    const int steps = static_cast<int>(std::ceil(horizontal / (0.5 * res)));
    int last = -1;
    for (int s = 0; s < steps; ++s) {
      const double t = static_cast<double>(s) / steps;
      const Eigen::Vector3d q = c + t * (end - c);
      if (q.z() < options.min_height_m || q.z() > options.max_height_m) continue;
      int x = 0, y = 0;
      if (!grid.CellOf(q.head<2>(), &x, &y) || (x == ex && y == ey)) continue;
      const int index = y * grid.width + x;
      if (index == last) continue;
      last = index;
      ++passes[static_cast<size_t>(index)];
    }
  }
  grid.data.assign(cells, OccupancyGrid::kUnknown);
  for (size_t i = 0; i < cells; ++i) {
    const double evidence = double(hits[i]) + double(passes[i]);
    if (evidence == 0) continue;
    const bool occupied = static_cast<int>(hits[i]) >= options.min_hits &&
                          hits[i] >= options.min_occupied_ratio * evidence;
    grid.data[i] = occupied ? OccupancyGrid::kOccupied : OccupancyGrid::kFree;
  }
  return grid;
}

OccupancyGrid BuildOccupancyGrid(const HybridMap& map, const std::vector<MapPoint>& points,
                                 const OccupancyGridOptions& options) {
  std::vector<Eigen::Vector3d> cameras;
  cameras.reserve(map.keyframes().size());
  for (const Keyframe& k : map.keyframes()) cameras.push_back(k.global_pose.translation());
  return BuildOccupancyGrid(cameras, points, options);
}

}  // namespace icgm
