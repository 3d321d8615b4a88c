// Anchor keyframes of the RGB-D front end (rgbd_frontend.h, frontend.anchor_keyframes).
//
// Every link of the keyframe chain carries the error of its registration, and where walkers
// fill the view those errors add up: on the Bonn crowd excerpt the pose relative to the first
// frame has drifted 16-25 cm (8-11 deg of pan) by frame 45, made in frames 13-31 where nearly
// every frame becomes a keyframe. The first keyframes of a run, made before any walker filled
// the view, saw a clean static room with a well-supported registration. Kept as anchors beyond
// the keyframe window, they give every later frame that still overlaps them one link whose
// error does not depend on the chain: the frame is registered to the anchor (its verified-static
// keypoints only, with the same matching, ICGM, evidence and refit as any reference), and the
// pose moves a share of the way towards the resulting estimate, so the drift since the anchor
// is pulled back at every frame instead of accumulating. Averaging the two by their
// registration covariances instead was measured worse: both are nearly singular along the
// pan-and-slide direction, and their information-weighted mean left both estimates by up to
// half a metre along it.
#pragma once

#include <string>

#include "core/common/pose.h"
#include "core/common/status.h"

namespace icgm {

struct AnchorOptions {
  // At most this many of the run's first keyframes become anchors (0: off). They are taken in
  // order, from the first keyframe, while each was registered with at least
  // keyframe_min_inliers inliers; the first keyframe that misses it closes the anchor set.
  int keyframes = 0;
  int keyframe_min_inliers = 150;
  // An anchor registration with fewer inliers is not used (the frame no longer overlaps it,
  // or the walkers hide it).
  int min_inliers = 40;
  // Share of the way from the chained estimate to the anchor's that the pose moves at each
  // frame (on SE(3), translation and rotation vector apart): a single anchor registration with
  // few inliers errs by centimetres, the chain's drift keeps its direction for seconds, so a
  // small share per frame averages the anchor's noise while it holds the drift.
  double gain = 0.1;
  // An anchor estimate further than this from the chained one is not used (0: no bound).
  double max_correction_m = 0.0;
  double max_correction_deg = 0.0;
  // The correction (applied after the motion prior) also moves the chain: the keyframes of the
  // window (not the anchors) and the velocity history are re-expressed by it, so later frames
  // registered to those keyframes continue from the corrected pose and the correction never
  // enters the predicted velocity (false: only the frame's own pose moves).
  bool moves_chain = true;
  // With select_by_evidence (and the map hypothesis off): the anchor's estimate is also offered
  // to the frame's registrations as one more hypothesis, the frame pair's matches that agree
  // with it, judged by the depth and edge evidence like the others. gain 0 with this: the
  // anchor only proposes, it never moves the pose.
  bool hypothesis = false;
};

// Whether a keyframe registered with `inliers` inliers (none for the run's first keyframe) may
// join `anchors_so_far` anchors, the set being still open.
bool QualifiesAsAnchor(const AnchorOptions& options, int anchors_so_far,
                       const int* registration_inliers);

struct AnchorCorrection {
  Status status = Status::Ok();
  Pose3 odom_camera = Pose3::Identity();  // the corrected T_odom_camera (when ok)
};

// The chained estimate `chained` moved `gain` of the way towards the anchor's estimate
// `anchored` (registered with `inliers` inliers); an error with the reason when the anchor
// estimate is not to be used (too few inliers, beyond the correction bound).
AnchorCorrection CorrectByAnchor(const Pose3& chained, const Pose3& anchored, int inliers,
                                 const AnchorOptions& options);

}  // namespace icgm
