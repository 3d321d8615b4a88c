// Ground truth for place recognition: for each query frame, the earlier frames showing the same
// place. Built either from ground-truth poses (a true revisit is an earlier frame within a
// distance and a viewing-angle difference, the criterion of icgm_map_eval) or from a
// ground-truth matrix image in which pixel (i, j) > 0 means frames i and j show the same place
// (the form the FAB-MAP and PIRF-Nav evaluations publish).
#pragma once

#include <cstdint>
#include <optional>
#include <vector>

#include <opencv2/core.hpp>

#include "core/common/pose.h"
#include "core/common/status.h"

namespace icgm {

// same_place[i]: the frames j < i (ascending) that show frame i's place.
struct PlaceTruth {
  std::vector<std::vector<int>> same_place;
  // unknown[i] != 0: frame i has no ground truth (no pose, e.g. a gap in the motion capture);
  // a loop from or to it is neither true nor false and it is no revisit. Empty: all known.
  std::vector<uint8_t> unknown;

  int num_frames() const { return static_cast<int>(same_place.size()); }
  bool Known(int frame) const;
  int NumUnknown() const;
  bool IsRevisit(int query) const;
  bool SamePlace(int query, int earlier) const;
  // Queries with at least one same-place earlier frame.
  int NumRevisits() const;
};

struct RevisitCriterion {
  double max_distance_m = 0.5;
  double max_angle_deg = 30.0;  // angle of the relative rotation
  // Only frames j <= i - min_frame_gap count (the place recognizer skips the most recent ones).
  int min_frame_gap = 1;
};

// From per-frame ground-truth poses (T_world_camera); a frame without a pose (nullopt) is
// neither a revisit nor the place of one.
PlaceTruth RevisitsFromPoses(const std::vector<std::optional<Pose3>>& poses,
                             const RevisitCriterion& criterion);

// From a ground-truth matrix image (any depth and channel count; a pixel counts when any
// channel is > 0) of at least num_frames x num_frames pixels; (i, j) or (j, i) set makes j a
// same-place frame of i, for j <= i - min_frame_gap. Fails with a reason for a smaller image.
Status PlaceTruthFromMatrix(const cv::Mat& matrix, int num_frames, int min_frame_gap,
                            PlaceTruth* truth);

}  // namespace icgm
