// Whole-frame depth residuals of a registration, and the dynamic regions they reveal
// (after ReFusion, Palazzolo et al., IROS 2019: what moved shows as a depth residual once the
// camera motion is known).
//
// Given T_ref_cur (p_ref = T_ref_cur * p_cur), every grid_step_px-th pixel of the current depth
// image is lifted, moved into the reference camera and projected; the reference depth there
// (nearest pixel) is compared with the moved point's depth. A residual within
//     tolerance(z) = abs_tolerance_m + rel_tolerance_per_m * z^2
// (structured-light noise grows with z^2) counts as agreeing static structure. A current point
// clearly in FRONT of the reference surface is something that was not there before (a walker
// who moved in); one clearly BEHIND it looks through where the reference saw something (the
// walker moved away, or plain occlusion by the viewpoint change).
//
// The residual serves twice:
//  - evidence for a motion hypothesis: the static scene agrees with the true motion wherever it
//    is seen, a walker only with the walker's motion (RgbdFrontend chooses among hypotheses);
//  - the current frame's dynamic mask: grid cells in front of the reference, cleaned of
//    isolated cells (depth noise, edges) and grown by dilate_cells, mark pixels whose features
//    must not enter registration, keyframes or the map.
#pragma once

#include <cmath>
#include <cstddef>

#include <opencv2/core.hpp>

#include "core/common/camera.h"
#include "core/common/pose.h"

namespace icgm {

class OptionReader;

struct DepthConsistencyOptions {
  int grid_step_px = 4;               // pixel spacing of the compared grid
  double abs_tolerance_m = 0.02;      // residual tolerance at z = 0
  double rel_tolerance_per_m = 0.01;  // ... growing with z^2 (m per m^2)
  double min_depth_m = 0.3;
  double max_depth_m = 6.0;
  // Dynamic mask: a cell needs at least this many in-front cells in its 3x3 neighbourhood
  // (itself included) to stay; the survivors are dilated by dilate_cells cells.
  int min_neighbours = 4;
  int dilate_cells = 3;
  // Edge agreement (CheckEdgeConsistency).
  double min_gradient = 20.0;   // grey levels between the pixel's horizontal/vertical neighbours
  double grey_tolerance = 12.0; // grey levels
  // The current frame's dynamic mask also takes the cells BEHIND the reference surface (a
  // walker moving away from the camera, as ReFusion thresholds the residual's magnitude); they
  // can also be background a walker uncovered, whose features are then only set aside for a
  // few frames. false: only what moved in front.
  bool mask_behind = false;
  // Dynamic masks grown over the surface the marked cells lie on before the dilation
  // (dynamic_region_fill.h): neighbouring cells within fill_max_step_m in depth, and within
  // fill_band_m of the marked cell's depth, join (0: no growth). The residuals mark a walker
  // only along the silhouette that moved; the growth takes the rest of the person.
  double fill_max_step_m = 0.0;
  double fill_band_m = 0.4;

  // A depth the comparison uses: finite and within [min_depth_m, max_depth_m].
  bool Usable(float z) const { return std::isfinite(z) && z >= min_depth_m && z <= max_depth_m; }
  // The residual that still counts as agreeing at depth z.
  double Tolerance(double z) const { return abs_tolerance_m + rel_tolerance_per_m * z * z; }
};

// Fills `options` from a `depth_consistency:` section; throws LoadError on bad values.
void ReadOptions(const OptionReader& reader, DepthConsistencyOptions* options);

struct DepthConsistency {
  size_t compared = 0;  // grid pixels valid in both images and projecting inside the reference
  size_t agreeing = 0;  // |residual| within tolerance
  size_t in_front = 0;  // current point in front of the reference surface
  size_t behind = 0;    // current point behind it
  double AgreeingShare() const { return compared ? double(agreeing) / double(compared) : 0.0; }
  double InFrontShare() const { return compared ? double(in_front) / double(compared) : 0.0; }
};

// Grid-resolution mask of the current image: a cell (row v / step, column u / step) is 255
// where the pixel moved in front of the reference surface (cleaned and dilated), else 0.
struct DynamicMask {
  cv::Mat cells;  // CV_8UC1, empty = nothing known
  int step_px = 4;
  bool empty() const { return cells.empty(); }
  // True when pixel `px` lies in a dynamic cell (false outside the image or without a mask).
  bool Contains(const cv::Point2f& px) const;
  // Share of the cells that are dynamic.
  double Coverage() const;
};

// Residual statistics of `depth_cur_m` against `depth_ref_m` (both CV_32FC1 metres, NaN/0 =
// none, registered to images of `intrinsics`) under `ref_cur`. With `mask` given, also the
// current frame's dynamic mask; with `reference_mask`, the reference image's cells that the
// current frame sees through (a current point behind them: what stood there has left), cleaned
// and grown the same way. Either image empty: zero counts, empty masks.
DepthConsistency CheckDepthConsistency(const cv::Mat& depth_ref_m, const cv::Mat& depth_cur_m,
                                       const Pose3& ref_cur, const CameraIntrinsics& intrinsics,
                                       const DepthConsistencyOptions& options,
                                       DynamicMask* mask = nullptr,
                                       DynamicMask* reference_mask = nullptr);

// Photometric agreement of the same motion on edges: every grid_step_px-th current pixel with
// depth whose grey gradient reaches min_gradient is moved into the reference and its grey
// value compared (nearest pixel); `agreeing` counts those within grey_tolerance. Static edges
// (desks, chairs, door frames) line up only under the camera's own motion, also where the
// depth cannot tell a sideways slide from a pan. `grey_*`: CV_8UC1 images of the two frames.
DepthConsistency CheckEdgeConsistency(const cv::Mat& grey_ref, const cv::Mat& grey_cur,
                                      const cv::Mat& depth_cur_m, const Pose3& ref_cur,
                                      const CameraIntrinsics& intrinsics,
                                      const DepthConsistencyOptions& options);

// The dynamic mask of the previous frame carried into the current one: every dynamic cell is
// lifted with the previous depth, moved by `cur_prev` (p_cur = cur_prev * p_prev) and marked
// where it lands, then grown by `grow_cells` for the walkers' own motion since. Cells without
// depth stay where they were.
DynamicMask PropagateDynamicMask(const DynamicMask& previous, const cv::Mat& depth_prev_m,
                                 const Pose3& cur_prev, const CameraIntrinsics& intrinsics,
                                 int grow_cells);

}  // namespace icgm
