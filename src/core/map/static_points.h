// Which map points are verified static: people removal for the dense map products.
//
// The front end keeps only ICGM-consistent features, but a keyframe's depth image also holds the
// walkers in view. A point is checked against every other keyframe that looks at it (after the
// depth-residual test of depth_consistency.h, between keyframes instead of consecutive frames):
// the point is moved into keyframe j's camera (map poses) and compared with j's stored depth at
// the pixel it projects to, with tolerance(z) = abs_tolerance_m + rel_tolerance_per_m * z^2:
//  - |residual| within the tolerance: j re-observes the point (agreeing);
//  - j's depth clearly BEHIND the point in the 3x3 neighbourhood of the pixel, or, where the
//    pixel has no depth, behind or missing in its 5x5 neighbourhood (missing everywhere only counts for a point nearer than hole_sees_through_within_m: the
//    sensor would have returned such a surface, so j looked past it beyond its range): j sees
//    through where the point was, so what stood there has moved (seen through);
//  - j's depth clearly in front: j's view is blocked there (no evidence).
// For points of keyframes without stored images (feature points only), another keyframe's
// feature point within feature_match_radius_m also counts as a re-observation.
// A point is static when at least min_agreeing_keyframes other keyframes, min_agreement_gap_s
// or more apart in time, re-observe it and at
// most max_see_through_share of the keyframes with evidence see through it. A walker seen once is
// seen through by the keyframes after it has left, and rarely re-observed at the same spot.
#pragma once

#include <cstddef>
#include <cstdint>
#include <functional>
#include <vector>

#include "core/map/hybrid_map.h"
#include "core/map/map_points.h"

namespace icgm {

class OptionReader;

struct StaticPointOptions {
  bool enabled = true;               // false: every point passes (comparison runs)
  int min_agreeing_keyframes = 1;    // other keyframes re-observing the point
  // ... at least this long before or after the point's keyframe: a walker is where it was a
  // moment ago, so only a later (or earlier) look confirms a point as static.
  double min_agreement_gap_s = 1.0;
  double max_see_through_share = 0.1;  // of the keyframes with evidence (agreeing + seeing through)
  double abs_tolerance_m = 0.02;
  double rel_tolerance_per_m = 0.005;  // m per m^2
  double min_depth_m = 0.3;          // in the other keyframe's camera
  double max_depth_m = 6.0;
  double hole_sees_through_within_m = 4.0;  // 0: a view without depth is never evidence
  double feature_match_radius_m = 0.05;
};

// Fills `options` from a `static_points:` section; throws LoadError on bad values.
void ReadOptions(const OptionReader& reader, StaticPointOptions* options);

struct StaticPointStats {
  size_t points = 0;
  size_t kept = 0;
  size_t seen_through = 0;  // removed: other keyframes see through them
  size_t unconfirmed = 0;   // removed: too few keyframes re-observe them
};

// The evidence found for one point.
struct PointEvidence {
  uint16_t agreeing = 0;      // re-observations counted (far enough apart in time)
  uint16_t seen_through = 0;
};

// Per point of `points` (from GatherMapPoints on `map`): 1 = verified static. `progress`, when
// given, is called with (keyframes done, keyframes); `evidence`, when given, receives each
// point's counts.
std::vector<uint8_t> VerifyStaticPoints(
    const HybridMap& map, const std::vector<MapPoint>& points, const StaticPointOptions& options,
    StaticPointStats* stats = nullptr,
    const std::function<void(size_t, size_t)>& progress = nullptr,
    std::vector<PointEvidence>* evidence = nullptr);

// The points whose flag is set.
std::vector<MapPoint> SelectPoints(const std::vector<MapPoint>& points,
                                   const std::vector<uint8_t>& keep);

}  // namespace icgm
