// Ground truth for place recognition: for each query frame, the earlier frames showing the same
// place. Built either from ground-truth poses (a true revisit is an earlier frame within a
// distance and a viewing-angle difference, the criterion of icgm_map_eval) or from a
// ground-truth matrix image in which pixel (i, j) > 0 means frames i and j show the same place
// (the form the FAB-MAP and PIRF-Nav evaluations publish).
//
// Optionally with a tolerance band (the "soft" ground truth of Schubert et al., "Visual Place
// Recognition: A Tutorial", 2023: matches in the soft but not the hard ground truth are
// neither true nor false positives): an earlier frame beyond the revisit bounds but within
// wider soft bounds shows largely the same view; a loop to it is neither true nor false, and it
// does not make the query a revisit (recall still counts the revisits within the strict bounds).
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
  // ambiguous[i]: the frames j < i (ascending) in the tolerance band of frame i: beyond the
  // revisit bounds, within the soft ones. A loop from i to one counts neither way. Empty: none.
  std::vector<std::vector<int>> ambiguous;

  int num_frames() const { return static_cast<int>(same_place.size()); }
  bool Known(int frame) const;
  int NumUnknown() const;
  bool IsRevisit(int query) const;
  bool SamePlace(int query, int earlier) const;
  bool Ambiguous(int query, int earlier) const;
  // A loop from query to earlier is judged true or false: both frames have ground truth and
  // the pair is not in the tolerance band.
  bool Judged(int query, int earlier) const;
  int NumAmbiguousPairs() const;
  // Queries with at least one same-place earlier frame.
  int NumRevisits() const;
};

struct RevisitCriterion {
  double max_distance_m = 0.5;
  double max_angle_deg = 30.0;  // angle of the relative rotation
  // Only frames j <= i - min_frame_gap count (the place recognizer skips the most recent ones).
  int min_frame_gap = 1;
  // Tolerance band: a pair beyond the bounds above but within both soft bounds is ambiguous.
  // A soft bound below its strict bound counts as the strict one (0, 0: no band).
  double soft_max_distance_m = 0.0;
  double soft_max_angle_deg = 0.0;
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
