// Export of map points as a point cloud file with PCL: voxel filter (pcl::VoxelGrid, one
// centroid per occupied voxel, colours averaged) and binary PCD or PLY.
#pragma once

#include <string>
#include <vector>

#include <pcl/point_cloud.h>
#include <pcl/point_types.h>

#include "core/common/status.h"
#include "core/map/map_points.h"

namespace icgm {

using ColouredCloud = pcl::PointCloud<pcl::PointXYZRGB>;

ColouredCloud ToPclCloud(const std::vector<MapPoint>& points);

// One point per voxel of edge `leaf_m` (the centroid of the voxel's points); leaf_m <= 0 returns
// the input. Voxel (i, j, k) holds the points with floor(p * (1 / leaf_m)) = (i, j, k), computed
// in float as pcl::VoxelGrid does (VoxelIndex).
ColouredCloud VoxelFilter(const ColouredCloud& cloud, double leaf_m);
Eigen::Vector3i VoxelIndex(const Eigen::Vector3f& p, double leaf_m);

// Writes binary PCD (".pcd") or binary PLY (".ply"), chosen by the extension; anything else,
// an empty cloud or a write error is a failed Status.
Status SaveCloud(const ColouredCloud& cloud, const std::string& path);
// Reads a ".pcd" or ".ply" file written by SaveCloud (tests, round trips).
Status LoadCloud(const std::string& path, ColouredCloud* cloud);

}  // namespace icgm
