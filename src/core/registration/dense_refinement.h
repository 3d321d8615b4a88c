// Dense refinement of an RGB-D relative pose on the pixels its depth residuals verify as static.
//
// A sparse registration rests on the matched keypoints. Among walkers those are mostly on the
// people, and the few on a poorly textured room (far walls, a plain floor, desks) leave a pan
// and a sideways slide nearly alike: the estimate is often 1-2 cm off while the room's surfaces
// would tell. RefineDense therefore aligns the whole depth image, like a projective ICP
// (point-to-plane, Gauss-Newton on a right perturbation T <- T * Exp(eps), pose.h order), but
// only on grid pixels that the current estimate already explains: a current point whose depth
// residual against the reference lies within a few sigmas of the sensor's depth noise,
// re-selected at every iteration. Whatever moved
// by more than that (a walker) never enters, and pixels in the given dynamic masks of either
// image are left out from the start. Optionally grey edges join with a photometric residual
// (static texture lines up only under the camera's own motion).
//
// The result is taken only when it keeps (nearly) as many pixels within the noise gate as the
// start (the whole frame's static evidence, min_agreement_ratio) and moved by at
// most max_correction_m / _deg: the refinement may polish a registration, never replace it.
#pragma once

#include <cstddef>

#include <opencv2/core.hpp>

#include "core/common/camera.h"
#include "core/common/pose.h"
#include "core/common/status.h"
#include "core/registration/depth_consistency.h"

namespace icgm {

class OptionReader;

struct DenseRefinementOptions {
  int grid_step_px = 4;             // pixel spacing of the aligned current pixels
  int iterations = 8;               // Gauss-Newton iterations at most
  int min_points = 300;             // fewer verified-static pixels: no refinement
  int normal_offset_px = 2;         // reference normals from neighbours this far apart
  // Depth noise of a structured-light sensor, sigma(z) = depth_sigma_m + depth_sigma_per_m2 z^2
  // (about Kinect-class noise: 3 mm at 1 m, 18 mm at 3 m). A pixel is static evidence while its
  // depth residual stays within gate_sigmas sigmas (a walker moving by a few centimetres per
  // frame leaves it, the depth_consistency tolerance is far looser).
  double depth_sigma_m = 0.0012;
  double depth_sigma_per_m2 = 0.0019;
  double gate_sigmas = 2.5;
  double huber_sigmas = 1.5;        // Huber threshold in units of each point's depth noise
  // The result must keep this share of the start's pixels within the noise gate (depth
  // quantization moves a few either way; a slide onto another surface loses many).
  double min_agreement_ratio = 0.95;
  double max_correction_m = 0.05;   // larger corrections of the start are rejected
  double max_correction_deg = 2.0;
  // Photometric residual on grey edges (gradient >= depth_consistency min_gradient), in grey
  // levels weighted against the depth residual as grey_sigma against the depth noise; 0: off.
  double grey_sigma = 0.0;
};

// Fills `options` from a `dense_refinement:` section; throws LoadError on bad values.
void ReadOptions(const OptionReader& reader, DenseRefinementOptions* options);

struct DenseRefinementResult {
  Status status = Status::Ok();  // why the start was kept (too few points, rejected, ...)
  Pose3 ref_cur = Pose3::Identity();
  size_t points = 0;            // verified-static depth pixels used in the last iteration
  size_t edge_points = 0;       // grey edge pixels used in the last iteration
  size_t agreeing_before = 0;   // depth-consistent grid pixels at the start ...
  size_t agreeing_after = 0;    // ... and at the refined pose
};

// Refines `ref_cur` (p_ref = ref_cur * p_cur). Depths CV_32FC1 metres (NaN/0 invalid), greys
// CV_8UC1 (may be empty: depth only). `cur_dynamic` / `ref_dynamic`: cells never used (may be
// empty). The static tolerance and depth range come from `consistency`. Never throws.
DenseRefinementResult RefineDense(const cv::Mat& depth_ref_m, const cv::Mat& depth_cur_m,
                                  const cv::Mat& grey_ref, const cv::Mat& grey_cur,
                                  const Pose3& ref_cur, const CameraIntrinsics& intrinsics,
                                  const DenseRefinementOptions& options,
                                  const DepthConsistencyOptions& consistency,
                                  const DynamicMask& cur_dynamic, const DynamicMask& ref_dynamic);

}  // namespace icgm
