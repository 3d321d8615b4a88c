#include "core/map_export/cloud_export.h"

#include <cmath>
#include <filesystem>

#include <pcl/filters/voxel_grid.h>
#include <pcl/io/pcd_io.h>
#include <pcl/io/ply_io.h>

namespace icgm {
namespace {

std::string Extension(const std::string& path) {
  return std::filesystem::path(path).extension().string();
}

}  // namespace

ColouredCloud ToPclCloud(const std::vector<MapPoint>& points) {
  ColouredCloud cloud;
  cloud.reserve(points.size());
  for (const MapPoint& m : points) {
    pcl::PointXYZRGB p;
    p.x = m.position_m.x();
    p.y = m.position_m.y();
    p.z = m.position_m.z();
    p.b = m.bgr[0];
    p.g = m.bgr[1];
    p.r = m.bgr[2];
    cloud.push_back(p);
  }
  cloud.width = static_cast<uint32_t>(cloud.size());
  cloud.height = 1;
  cloud.is_dense = true;
  return cloud;
}

Eigen::Vector3i VoxelIndex(const Eigen::Vector3f& p, double leaf_m) {
  const float inverse = 1.0f / static_cast<float>(leaf_m);
  return {static_cast<int>(std::floor(p.x() * inverse)),
          static_cast<int>(std::floor(p.y() * inverse)),
          static_cast<int>(std::floor(p.z() * inverse))};
}

ColouredCloud VoxelFilter(const ColouredCloud& cloud, double leaf_m) {
  if (leaf_m <= 0.0 || cloud.empty()) return cloud;
  ColouredCloud::Ptr input(new ColouredCloud(cloud));
  pcl::VoxelGrid<pcl::PointXYZRGB> grid;
  grid.setInputCloud(input);
  const float leaf = static_cast<float>(leaf_m);
  grid.setLeafSize(leaf, leaf, leaf);
  grid.setDownsampleAllData(true);  // average the colours too
  ColouredCloud out;
  grid.filter(out);
  return out;
}

Status SaveCloud(const ColouredCloud& cloud, const std::string& path) {
  if (cloud.empty()) return Status::Error("no points to write to '" + path + "'");
  const std::string ext = Extension(path);
  int rc = -1;
  try {
    if (ext == ".pcd") {
      rc = pcl::io::savePCDFileBinary(path, cloud);
    } else if (ext == ".ply") {
      rc = pcl::io::savePLYFile(path, cloud, /*binary_mode=*/true);
    } else {
      return Status::Error("'" + path + "': unknown cloud format (use .pcd or .ply)");
    }
  } catch (const std::exception& e) {
    return Status::Error("cannot write '" + path + "': " + e.what());
  }
  if (rc != 0) return Status::Error("cannot write '" + path + "'");
  return Status::Ok();
}

Status LoadCloud(const std::string& path, ColouredCloud* cloud) {
  const std::string ext = Extension(path);
  int rc = -1;
  try {
    if (ext == ".pcd") {
      rc = pcl::io::loadPCDFile(path, *cloud);
    } else if (ext == ".ply") {
      rc = pcl::io::loadPLYFile(path, *cloud);
    } else {
      return Status::Error("'" + path + "': unknown cloud format (use .pcd or .ply)");
    }
  } catch (const std::exception& e) {
    return Status::Error("cannot read '" + path + "': " + e.what());
  }
  if (rc != 0) return Status::Error("cannot read '" + path + "'");
  return Status::Ok();
}

}  // namespace icgm
