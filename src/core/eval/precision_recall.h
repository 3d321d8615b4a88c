// Precision and recall of a place recognizer against ground truth (PlaceTruth), swept over the
// loop-acceptance threshold. Each query frame has the recognizer's best earlier candidate and
// its score; at threshold t the query claims a loop when score >= t. A claimed loop is a true
// positive when the candidate shows the query's place, else a false positive; a loop from or to
// a frame without ground truth, or into the truth's tolerance band, is neither. Recall divides
// the true positives by the queries that are revisits, less the revisits whose claimed loop goes
// to a frame without ground truth (whether they found their place cannot be judged: neither
// found nor missed); precision by the claimed loops (1 when nothing is claimed). A revisit whose
// loop goes into the band is missed (the band's frames lie beyond the revisit bounds). Recall at
// 100 % precision is the largest recall of a threshold without a false positive, the figure FAB-MAP
// and PIRF-Nav report.
#pragma once

#include <vector>

#include "core/eval/place_truth.h"

namespace icgm {

struct PlaceQuery {
  int query = 0;
  int candidate = -1;  // best earlier frame, -1 when there was none
  double score = 0.0;
};

struct PrecisionRecallPoint {
  double threshold = 0.0;
  int true_positives = 0;
  int false_positives = 0;
  // Revisits whose claimed loop goes to a frame without ground truth: left out of recall.
  int undetermined = 0;
  double precision = 1.0;
  double recall = 0.0;
};

struct PrecisionRecallCurve {
  // One point per distinct candidate score, thresholds descending (recall non-decreasing).
  std::vector<PrecisionRecallPoint> points;
  int revisits = 0;  // queries with a same-place earlier frame
  int queries = 0;
  double recall_at_full_precision = 0.0;
  double threshold_at_full_precision = 0.0;  // lowest threshold reaching it (inf: none)
};

// Precision and recall when loops are accepted at score >= threshold.
PrecisionRecallPoint EvaluateAtThreshold(const std::vector<PlaceQuery>& queries,
                                         const PlaceTruth& truth, double threshold);

PrecisionRecallCurve SweepPrecisionRecall(const std::vector<PlaceQuery>& queries,
                                          const PlaceTruth& truth);

}  // namespace icgm
