#include "core/map_export/map_products.h"

#include "core/map_export/cloud_export.h"

namespace icgm {

Status BuildMapProducts(const HybridMap& map, const MapExportOptions& options,
                        MapProducts* products, const MapProductsProgress& progress,
                        bool keep_points) {
  if (map.empty()) return Status::Error("map products: the map has no keyframes");
  std::vector<MapPoint> points = GatherMapPoints(map, options.cloud);
  if (points.empty()) return Status::Error("map products: the map has no points");
  MapProducts out;
  std::vector<MapPoint> kept = SelectPoints(
      points, VerifyStaticPoints(map, points, options.static_points, &out.stats, progress));
  out.grid = BuildOccupancyGrid(map, kept, options.grid);
  const ColouredCloud voxels = VoxelFilter(ToPclCloud(kept), options.cloud.voxel_m);
  out.cloud.reserve(voxels.size());
  for (const pcl::PointXYZRGB& p : voxels) {
    MapPoint m;
    m.position_m = Eigen::Vector3f(p.x, p.y, p.z);
    m.bgr = cv::Vec3b(p.b, p.g, p.r);
    out.cloud.push_back(m);
  }
  if (keep_points) {
    out.points = std::move(points);
    out.static_points = std::move(kept);
  }
  *products = std::move(out);
  return Status::Ok();
}

}  // namespace icgm
