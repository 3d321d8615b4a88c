#include "core/map/map_points.h"

#include "core/common/option_reader.h"

namespace icgm {

void ReadOptions(const OptionReader& reader, MapCloudOptions* o) {
  reader.Read("min_depth_m", &o->min_depth_m, 0.0, 100.0);
  reader.Read("max_depth_m", &o->max_depth_m, 0.0, 100.0);
  reader.Read("pixel_step", &o->pixel_step, 1, 64);
  reader.Read("voxel_m", &o->voxel_m, 0.001, 10.0);
  if (!(o->max_depth_m > o->min_depth_m)) {
    throw LoadError(reader.path() + ".max_depth_m: must be > min_depth_m");
  }
}

bool ImagePoint(const KeyframeImages& images, int u, int v, Eigen::Vector3d* point_camera_m) {
  const double z = images.DepthM(u, v);
  if (z <= 0.0) return false;
  *point_camera_m = images.intrinsics.BackProject(u, v, z);
  return true;
}

bool HasKeyframeImages(const HybridMap& map) {
  for (const Keyframe& k : map.keyframes()) {
    if (!k.images.empty()) return true;
  }
  return false;
}

std::vector<MapPoint> GatherMapPoints(const HybridMap& map, const MapCloudOptions& options) {
  std::vector<MapPoint> out;
  for (const Keyframe& k : map.keyframes()) {
    const Eigen::Isometry3d& pose = k.global_pose;
    if (k.images.empty()) {
      for (size_t i = 0; i < k.points_m.size() && i < k.keypoints.size(); ++i) {
        const Eigen::Vector3d& p = k.points_m[i];
        if (!p.allFinite() || p.z() < options.min_depth_m || p.z() > options.max_depth_m) continue;
        MapPoint m;
        m.position_m = (pose * p).cast<float>();
        m.keyframe_id = k.id;
        m.pixel = k.keypoints[i].pt;
        out.push_back(m);
      }
      continue;
    }
    const KeyframeImages& images = k.images;
    const bool colour = !images.bgr.empty();
    for (int v = 0; v < images.depth_mm.rows; v += options.pixel_step) {
      for (int u = 0; u < images.depth_mm.cols; u += options.pixel_step) {
        Eigen::Vector3d p;
        if (!ImagePoint(images, u, v, &p)) continue;
        if (p.z() < options.min_depth_m || p.z() > options.max_depth_m) continue;
        MapPoint m;
        m.position_m = (pose * p).cast<float>();
        if (colour) m.bgr = images.bgr.at<cv::Vec3b>(v, u);
        m.keyframe_id = k.id;
        m.pixel = images.FullPixel(u, v);
        m.from_image = true;
        out.push_back(m);
      }
    }
  }
  return out;
}

}  // namespace icgm
