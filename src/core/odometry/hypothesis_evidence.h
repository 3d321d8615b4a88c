// Scores of the motion hypotheses of one frame pair by their whole-frame evidence
// (select_by_evidence, rgbd_frontend.h): grid pixels whose depth the motion explains
// (depth_consistency.h CheckDepthConsistency) and edge pixels whose grey value lines up
// (CheckEdgeConsistency).
//
// Summed raw, the depth count dominates: it is an order of magnitude larger than the edge count
// and hardly discriminates where the room lies 3-5 m away, since the depth tolerance grows with
// z^2 (11 cm at 3 m) and a wrong motion still explains most of a far wall. A walker close to the
// camera then tips the sum: on the simulated hand-held crowd, the set a walker formed (15-60
// inliers, 80-100% on the walker) won over the static set (100-300 inliers) with 5-10% more
// agreeing depth pixels while explaining 25-40% fewer edge pixels.
// Normalized, each cue is divided by its largest count among the hypotheses before the two are
// summed, so each cue weighs by how much the hypotheses differ in it, whatever its pixel count.
#pragma once

#include <cstddef>
#include <vector>

#include <opencv2/core/mat.hpp>
#include <opencv2/core/types.hpp>

#include "core/common/pose.h"

namespace icgm {

struct HypothesisEvidence {
  size_t depth_agreeing = 0;  // grid pixels whose depth the motion explains
  size_t edges_agreeing = 0;  // edge pixels whose grey value the motion explains
};

// One score per hypothesis (higher is better). `normalized` false: depth + edge counts (the
// pipeline's original choice); true: depth / max depth + edges / max edges over the hypotheses.
std::vector<double> EvidenceScores(const std::vector<HypothesisEvidence>& hypotheses,
                                   bool normalized);

// Cells of a cols x rows grid over an image of `image` size that hold at least one of `px`
// (points outside the image are ignored): how widely a consistent set spreads over the view.
size_t SpreadCells(const std::vector<cv::Point2f>& px, cv::Size image, int cols, int rows);

// Median of `depth_m` (CV_32F, metres) at the pixels `px` (nearest pixel; pixels outside the
// image or without finite positive depth are skipped); NaN where none has depth.
double MedianDepthAt(const cv::Mat& depth_m, const std::vector<cv::Point2f>& px);

// Depth order among motion hypotheses (evidence_depth_order_margin): walkers stand in front of
// the room, so of two consistent sets that explain the frame about as well, the one lying
// farther is the room's. Among the hypotheses whose score is at least (1 - margin) x the best
// score and that hold at least min_inliers inliers, the one with the farthest median inlier
// depth replaces `chosen` when its median lies at least min_gap_m beyond `chosen`'s (NaN
// depths never win; of equally far sets, the later one: the prediction's set is judged last).
// Returns the index of the winner (`chosen` when none qualifies).
size_t ChooseByDepthOrder(const std::vector<double>& score,
                          const std::vector<double>& median_depth_m,
                          const std::vector<size_t>& inliers, size_t chosen, double margin,
                          double min_gap_m, size_t min_inliers);

// Prediction gate among motion hypotheses (evidence_prediction_gate_m): the camera is carried
// by a hand, so a motion that puts the frame far from the constant-velocity prediction is
// implausible when another consistent set stays near it. When `chosen` lies more than gate_m
// from the prediction (`from_prediction_m`, translation between the two poses of the current
// frame; NaN: unknown, never inside), the best-scored hypothesis within gate_m holding at least
// min_inliers inliers replaces it. Returns the index of the winner (`chosen` when it lies within
// the gate or none qualifies).
size_t ChooseWithinPredictionGate(const std::vector<double>& score,
                                  const std::vector<double>& from_prediction_m,
                                  const std::vector<size_t>& inliers, size_t chosen,
                                  double gate_m, size_t min_inliers);

// Where a hypothesis's matches came from (rgbd_frontend.cpp ChooseByEvidence).
enum class HypothesisKind {
  kIcgm,        // the matches ICGM kept (the registration without the evidence choice)
  kLeftOut,     // the matches the first registration left out: a second consistent set
  kPrediction,  // the matches agreeing with the predicted motion
  kMap,         // the matches agreeing with the map's (or anchor's) location
  kSeed,        // the ICGM-kept matches with a further RANSAC seed (evidence_ransac_runs)
  kFar,         // the ICGM-kept matches beyond evidence_far_hypothesis_m
};
const char* HypothesisKindName(HypothesisKind kind);  // "icgm", "left_out", ...

// One hypothesis as the evidence choice judged it (per frame, for diagnosis: which set won and
// by how much; the frame's result carries them, the offline tool's report writes them).
struct JudgedHypothesis {
  HypothesisKind kind = HypothesisKind::kIcgm;
  size_t inliers = 0;
  Pose3 relative_pose = Pose3::Identity();  // T_reference_current as registered
  HypothesisEvidence evidence;  // reference plus, with evidence_from_previous_frame, previous
  double score = 0.0;           // EvidenceScores (+ map support)
  // Distance to the predicted motion, translation / 5 cm + rotation / 2 deg (the measure of
  // evidence_margin); NaN without a prediction.
  double prediction_distance = 0.0;
  std::vector<cv::Point2f> inlier_px;  // current-frame pixels of its inliers (before any refit)
  double median_depth_m = 0.0;  // median reference depth of its inliers (NaN: none with depth)
};

// Near-set test (frontend.prior_gate_near_m): walkers stand in front of the room, so a chosen
// consistent set whose inliers' median reference depth lies below near_m was most likely made
// on a walker. False when near_m <= 0, `chosen` is no index into `judged` (no evidence choice
// was made) or its median depth is unknown (NaN).
bool ChosenSetNearerThan(const std::vector<JudgedHypothesis>& judged, int chosen, double near_m);

}  // namespace icgm
