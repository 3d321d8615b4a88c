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

namespace icgm {

struct HypothesisEvidence {
  size_t depth_agreeing = 0;  // grid pixels whose depth the motion explains
  size_t edges_agreeing = 0;  // edge pixels whose grey value the motion explains
};

// One score per hypothesis (higher is better). `normalized` false: depth + edge counts (the
// pipeline's original choice); true: depth / max depth + edges / max edges over the hypotheses.
std::vector<double> EvidenceScores(const std::vector<HypothesisEvidence>& hypotheses,
                                   bool normalized);

}  // namespace icgm
