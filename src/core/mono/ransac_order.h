// The order in which a RANSAC (OpenCV solvePnPRansac, findEssentialMat) receives its
// correspondences. OpenCV draws its minimal samples from a fixed internal seed, so the same
// input always gives the same model; handing the correspondences over in an order drawn from
// another seed gives another, equally valid, draw of the same estimator (repeats of a run
// without ICGM, whose other stages are deterministic, for paired comparisons over draws).
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

namespace icgm {

// A permutation of 0..n-1: the identity for seed 0, else a shuffle drawn from `seed` (the same
// permutation for the same n and seed).
std::vector<size_t> RansacOrder(size_t n, uint64_t seed);

// `flags_in_order[i]` belongs to correspondence `order[i]`: the flags in input order.
std::vector<uint8_t> FlagsInInputOrder(const std::vector<uint8_t>& flags_in_order,
                                       const std::vector<size_t>& order);

}  // namespace icgm
