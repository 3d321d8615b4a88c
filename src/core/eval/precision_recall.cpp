#include "core/eval/precision_recall.h"

#include <algorithm>
#include <limits>

namespace icgm {

namespace {

void Finish(int revisits, PrecisionRecallPoint* p) {
  const int claimed = p->true_positives + p->false_positives;
  p->precision = claimed > 0 ? static_cast<double>(p->true_positives) / claimed : 1.0;
  const int judged = revisits - p->undetermined;
  p->recall = judged > 0 ? static_cast<double>(p->true_positives) / judged : 0.0;
}

// A revisit (with ground truth) whose loop goes to a frame without: whether it found its place
// cannot be judged.
bool Undetermined(const PlaceQuery& q, const PlaceTruth& truth) {
  return q.candidate >= 0 && truth.IsRevisit(q.query) && !truth.Known(q.candidate);
}

}  // namespace

PrecisionRecallPoint EvaluateAtThreshold(const std::vector<PlaceQuery>& queries,
                                         const PlaceTruth& truth, double threshold) {
  PrecisionRecallPoint p;
  p.threshold = threshold;
  for (const PlaceQuery& q : queries) {
    if (q.candidate < 0 || q.score < threshold) continue;
    p.undetermined += Undetermined(q, truth);
    if (!truth.Judged(q.query, q.candidate)) continue;  // neither true nor false
    (truth.SamePlace(q.query, q.candidate) ? p.true_positives : p.false_positives) += 1;
  }
  Finish(truth.NumRevisits(), &p);
  return p;
}

PrecisionRecallCurve SweepPrecisionRecall(const std::vector<PlaceQuery>& queries,
                                          const PlaceTruth& truth) {
  PrecisionRecallCurve curve;
  curve.revisits = truth.NumRevisits();
  curve.queries = static_cast<int>(queries.size());
  curve.threshold_at_full_precision = std::numeric_limits<double>::infinity();
  std::vector<const PlaceQuery*> claimed;
  for (const PlaceQuery& q : queries) {
    // A loop from or to a frame without ground truth, or into the tolerance band, is neither
    // true nor false; a revisit's loop to a frame without ground truth leaves recall.
    if (q.candidate >= 0 && (truth.Judged(q.query, q.candidate) || Undetermined(q, truth))) {
      claimed.push_back(&q);
    }
  }
  std::sort(claimed.begin(), claimed.end(),
            [](const PlaceQuery* a, const PlaceQuery* b) { return a->score > b->score; });
  PrecisionRecallPoint p;
  for (size_t k = 0; k < claimed.size(); ++k) {
    const PlaceQuery& q = *claimed[k];
    if (Undetermined(q, truth)) {
      ++p.undetermined;
    } else {
      (truth.SamePlace(q.query, q.candidate) ? p.true_positives : p.false_positives) += 1;
    }
    // Queries of equal score are accepted together by one threshold.
    if (k + 1 < claimed.size() && claimed[k + 1]->score == q.score) continue;
    p.threshold = q.score;
    Finish(curve.revisits, &p);
    curve.points.push_back(p);
    if (p.false_positives == 0 && p.recall >= curve.recall_at_full_precision) {
      curve.recall_at_full_precision = p.recall;
      curve.threshold_at_full_precision = p.threshold;
    }
  }
  return curve;
}

}  // namespace icgm
