// Dynamic regions grown over the surface they lie on.
//
// Depth residuals after registration (depth_consistency.h) mark a walker only where it moved
// over the background: a band along its leading silhouette. The clothing inside that band
// agrees with the reference surface (the body's surface hardly changes depth as it slides
// sideways), so its features pass as static. A walker is a surface of continuous depth in
// front of the room: growing the marked cells over neighbours of nearly equal depth, and no
// further than a band around the depth of the cell they grew from, covers the whole person
// while the depth step to the background stops the growth (the floor at the walker's feet,
// continuous with them, is taken only within the band).
#pragma once

#include <opencv2/core.hpp>

namespace icgm {

struct SurfaceFillOptions {
  double max_step_m = 0.0;  // largest depth step between 4-neighbour cells (0: no growth)
  double band_m = 0.4;      // largest depth difference from the seed cell the growth started at
  double min_depth_m = 0.3;
  double max_depth_m = 6.0;
};

// `seeds`: CV_8UC1 grid (cell (gv, gu) samples pixel (gv * step_px, gu * step_px) of
// `depth_m`, CV_32FC1 metres), non-zero = marked. Returns the seeds plus every cell connected
// to one of them by 4-neighbour steps of at most max_step_m whose depth lies within band_m of
// that seed's, as 255. Cells without usable depth neither grow nor are grown into. An empty or
// mistyped depth image, or max_step_m <= 0, returns the seeds unchanged.
cv::Mat FillConnectedSurface(const cv::Mat& seeds, const cv::Mat& depth_m, int step_px,
                             const SurfaceFillOptions& options);

}  // namespace icgm
