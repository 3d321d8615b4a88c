#include "core/map/static_points.h"

#include <algorithm>
#include <cmath>
#include <unordered_map>

#include <Eigen/Geometry>

#include "core/common/option_reader.h"

namespace icgm {
namespace {

// A keyframe's view for the projection test, in float for speed.
struct View {
  int id = -1;
  Time stamp;
  Eigen::Matrix3f R_cam_map;
  Eigen::Vector3f t_cam_map;
  Eigen::Vector3f centre_m;
  const KeyframeImages* images = nullptr;
};

enum class Evidence { kNone, kAgrees, kSeesThrough };

Evidence Check(const View& view, const Eigen::Vector3f& point_map,
               const StaticPointOptions& options) {
  const Eigen::Vector3f p = view.R_cam_map * point_map + view.t_cam_map;
  const float z = p.z();
  if (z < options.min_depth_m || z > options.max_depth_m) return Evidence::kNone;
  const CameraIntrinsics& k = view.images->intrinsics;
  const int u = static_cast<int>(std::lround(k.fx_px * p.x() / z + k.cx_px));
  const int v = static_cast<int>(std::lround(k.fy_px * p.y() / z + k.cy_px));
  const cv::Mat& depth = view.images->depth_mm;
  if (u < 0 || v < 0 || u >= depth.cols || v >= depth.rows) return Evidence::kNone;
  const uint16_t d_mm = depth.at<uint16_t>(v, u);
  const double d = d_mm * 1e-3;
  const double tolerance = options.abs_tolerance_m + options.rel_tolerance_per_m * z * z;
  if (d_mm != 0 && std::abs(d - z) <= tolerance) return Evidence::kAgrees;
  if (d_mm != 0 && d < z) return Evidence::kNone;  // blocked: something in front in this view
  // Seen through when the 3x3 neighbourhood lies behind the point (a single pixel behind may be
  // an edge or depth noise), or, without depth at the pixel itself, when the 5x5 neighbourhood
  // holds nothing but depth behind it or none.
  const int radius = d_mm != 0 ? 1 : 2;
  int behind = 0;
  for (int dv = -radius; dv <= radius; ++dv) {
    for (int du = -radius; du <= radius; ++du) {
      const int uu = u + du, vv = v + dv;
      if (uu < 0 || vv < 0 || uu >= depth.cols || vv >= depth.rows) continue;
      const uint16_t n_mm = depth.at<uint16_t>(vv, uu);
      if (n_mm == 0) continue;
      if (n_mm * 1e-3 <= z + tolerance) return Evidence::kNone;
      ++behind;
    }
  }
  // No depth anywhere around: the view ends beyond the sensor's range behind the point, which a
  // surface this near would have returned.
  if (behind == 0 && !(z <= options.hole_sees_through_within_m)) return Evidence::kNone;
  return Evidence::kSeesThrough;
}

// Feature points of keyframes without images, hashed by cell of feature_match_radius_m.
class FeatureHash {
 public:
  FeatureHash(const std::vector<MapPoint>& points, double cell_m) : cell_m_(cell_m) {
    for (const MapPoint& p : points) {
      if (!p.from_image) cells_[Key(p.position_m)].push_back(&p);
    }
  }
  // Distinct keyframes other than the point's own, accepted by `counts`, with a feature within
  // the radius.
  int Reobserving(const MapPoint& point, const std::function<bool(int)>& counts) const {
    std::vector<int> ids;
    const Eigen::Vector3i c = Cell(point.position_m);
    for (int dx = -1; dx <= 1; ++dx)
      for (int dy = -1; dy <= 1; ++dy)
        for (int dz = -1; dz <= 1; ++dz) {
          const auto it = cells_.find(CellKey(c + Eigen::Vector3i(dx, dy, dz)));
          if (it == cells_.end()) continue;
          for (const MapPoint* q : it->second) {
            if (q->keyframe_id != point.keyframe_id && counts(q->keyframe_id) &&
                (q->position_m - point.position_m).norm() <= cell_m_) {
              ids.push_back(q->keyframe_id);
            }
          }
        }
    std::sort(ids.begin(), ids.end());
    return static_cast<int>(std::unique(ids.begin(), ids.end()) - ids.begin());
  }

 private:
  Eigen::Vector3i Cell(const Eigen::Vector3f& p) const {
    return (p.cast<double>() / cell_m_).array().floor().cast<int>();
  }
  static int64_t CellKey(const Eigen::Vector3i& c) {
    return (int64_t(c.x() & 0x1FFFFF) << 42) | (int64_t(c.y() & 0x1FFFFF) << 21) |
           int64_t(c.z() & 0x1FFFFF);
  }
  int64_t Key(const Eigen::Vector3f& p) const { return CellKey(Cell(p)); }
  double cell_m_;
  std::unordered_map<int64_t, std::vector<const MapPoint*>> cells_;
};

}  // namespace

void ReadOptions(const OptionReader& reader, StaticPointOptions* o) {
  reader.Read("enabled", &o->enabled);
  reader.Read("min_agreeing_keyframes", &o->min_agreeing_keyframes, 0, 1000);
  reader.Read("min_agreement_gap_s", &o->min_agreement_gap_s, 0.0, 1e6);
  reader.Read("max_see_through_share", &o->max_see_through_share, 0.0, 1.0);
  reader.Read("abs_tolerance_m", &o->abs_tolerance_m, 0.0, 1.0);
  reader.Read("rel_tolerance_per_m", &o->rel_tolerance_per_m, 0.0, 1.0);
  reader.Read("min_depth_m", &o->min_depth_m, 0.0, 100.0);
  reader.Read("max_depth_m", &o->max_depth_m, 0.0, 100.0);
  reader.Read("hole_sees_through_within_m", &o->hole_sees_through_within_m, 0.0, 100.0);
  reader.Read("feature_match_radius_m", &o->feature_match_radius_m, 1e-4, 10.0);
  if (!(o->max_depth_m > o->min_depth_m)) {
    throw LoadError(reader.path() + ".max_depth_m: must be > min_depth_m");
  }
}

std::vector<uint8_t> VerifyStaticPoints(const HybridMap& map, const std::vector<MapPoint>& points,
                                        const StaticPointOptions& options,
                                        StaticPointStats* stats,
                                        const std::function<void(size_t, size_t)>& progress,
                                        std::vector<PointEvidence>* evidence_out) {
  StaticPointStats local;
  local.points = points.size();
  std::vector<uint8_t> keep(points.size(), 1);
  if (evidence_out) evidence_out->assign(points.size(), PointEvidence());
  if (!options.enabled) {
    local.kept = points.size();
    if (stats) *stats = local;
    return keep;
  }
  std::vector<View> views;
  for (const Keyframe& k : map.keyframes()) {
    if (k.images.empty()) continue;
    View v;
    v.id = k.id;
    v.stamp = k.stamp;
    const Eigen::Isometry3d cam_map = k.global_pose.inverse();
    v.R_cam_map = cam_map.linear().cast<float>();
    v.t_cam_map = cam_map.translation().cast<float>();
    v.centre_m = k.global_pose.translation().cast<float>();
    v.images = &k.images;
    views.push_back(v);
  }
  const FeatureHash features(points, options.feature_match_radius_m);
  const float reach_m = static_cast<float>(options.max_depth_m);
  // Points are grouped by keyframe (GatherMapPoints' order); the candidate views of a keyframe are
  // those whose camera is within reach of any of its points.
  size_t begin = 0;
  const size_t keyframes = static_cast<size_t>(map.size());
  size_t done_keyframes = 0;
  while (begin < points.size()) {
    const int id = points[begin].keyframe_id;
    size_t end = begin;
    Eigen::Vector3f lo = points[begin].position_m, hi = lo;
    while (end < points.size() && points[end].keyframe_id == id) {
      lo = lo.cwiseMin(points[end].position_m);
      hi = hi.cwiseMax(points[end].position_m);
      ++end;
    }
    std::vector<const View*> candidates;
    std::vector<uint8_t> apart;  // far enough in time to confirm
    const Time stamp = map.keyframe(id).stamp;
    const auto far_in_time = [&](int other) {
      return std::abs(DurationSeconds(map.keyframe(other).stamp, stamp)) >=
             options.min_agreement_gap_s;
    };
    for (const View& v : views) {
      if (v.id == id) continue;
      const Eigen::Vector3f nearest = v.centre_m.cwiseMax(lo).cwiseMin(hi);
      if ((nearest - v.centre_m).norm() > reach_m) continue;
      candidates.push_back(&v);
      apart.push_back(std::abs(DurationSeconds(v.stamp, stamp)) >= options.min_agreement_gap_s);
    }
    for (size_t i = begin; i < end; ++i) {
      const MapPoint& point = points[i];
      int agreeing = point.from_image ? 0 : features.Reobserving(point, far_in_time);
      int seen_through = 0;
      for (size_t c = 0; c < candidates.size(); ++c) {
        const Evidence e = Check(*candidates[c], point.position_m, options);
        if (e == Evidence::kAgrees && apart[c]) ++agreeing;
        if (e == Evidence::kSeesThrough) ++seen_through;
      }
      const int evidence = agreeing + seen_through;
      if (evidence_out) {
        (*evidence_out)[i].agreeing = static_cast<uint16_t>(std::min(agreeing, 65535));
        (*evidence_out)[i].seen_through = static_cast<uint16_t>(std::min(seen_through, 65535));
      }
      if (seen_through > 0 && seen_through > options.max_see_through_share * evidence) {
        keep[i] = 0;
        ++local.seen_through;
      } else if (agreeing < options.min_agreeing_keyframes) {
        keep[i] = 0;
        ++local.unconfirmed;
      }
    }
    begin = end;
    ++done_keyframes;
    if (progress) progress(std::min(done_keyframes, keyframes), keyframes);
  }
  local.kept = local.points - local.seen_through - local.unconfirmed;
  if (stats) *stats = local;
  return keep;
}

std::vector<MapPoint> SelectPoints(const std::vector<MapPoint>& points,
                                   const std::vector<uint8_t>& keep) {
  std::vector<MapPoint> out;
  out.reserve(points.size());
  for (size_t i = 0; i < points.size() && i < keep.size(); ++i) {
    if (keep[i]) out.push_back(points[i]);
  }
  return out;
}

}  // namespace icgm
