// The map's 3D points in the map frame, each with where it came from (keyframe and pixel), as
// the input of the dense map products (static_points.h, occupancy_grid.h, icgm_map_export).
//  - Keyframes with stored images (Keyframe::images) give one point per stored pixel with depth
//    in [min_depth_m, max_depth_m] (every pixel_step-th pixel in both directions), coloured by
//    the stored colour image;
//  - keyframes without images give their ICGM-robust feature points (grey).
#pragma once

#include <vector>

#include <Eigen/Core>
#include <opencv2/core.hpp>

#include "core/map/hybrid_map.h"

namespace icgm {

class OptionReader;

struct MapPoint {
  Eigen::Vector3f position_m = Eigen::Vector3f::Zero();  // map frame
  cv::Vec3b bgr{128, 128, 128};
  int keyframe_id = -1;
  cv::Point2f pixel;  // in the keyframe's full image (colour camera pixels)
  bool from_image = false;  // a depth-image pixel (else a feature point)
};

struct MapCloudOptions {
  double min_depth_m = 0.3;
  double max_depth_m = 5.0;   // farther structured-light depth is too noisy for the cloud
  int pixel_step = 1;         // of the stored (already subsampled) images
  double voxel_m = 0.02;      // leaf of the exported cloud's voxel filter
};

// Fills `options` from a `map_cloud:` section; throws LoadError on bad values.
void ReadOptions(const OptionReader& reader, MapCloudOptions* options);

// Camera-frame point of stored pixel (u, v) of `images` (false without depth there).
bool ImagePoint(const KeyframeImages& images, int u, int v, Eigen::Vector3d* point_camera_m);

// Every keyframe's points (see above), keyframes in id order.
std::vector<MapPoint> GatherMapPoints(const HybridMap& map, const MapCloudOptions& options);

// Whether any keyframe of `map` has stored images.
bool HasKeyframeImages(const HybridMap& map);

}  // namespace icgm
