#include "core/mono/ransac_order.h"

#include <algorithm>
#include <numeric>
#include <random>

namespace icgm {

std::vector<size_t> RansacOrder(size_t n, uint64_t seed) {
  std::vector<size_t> order(n);
  std::iota(order.begin(), order.end(), size_t{0});
  if (seed == 0) return order;
  std::mt19937_64 rng(seed);
  // Fisher-Yates with the engine's raw output (std::shuffle's draws are library-defined).
  for (size_t i = n; i > 1; --i) std::swap(order[i - 1], order[rng() % i]);
  return order;
}

std::vector<uint8_t> FlagsInInputOrder(const std::vector<uint8_t>& flags_in_order,
                                       const std::vector<size_t>& order) {
  std::vector<uint8_t> out(order.size(), 0);
  for (size_t i = 0; i < order.size() && i < flags_in_order.size(); ++i) {
    out[order[i]] = flags_in_order[i];
  }
  return out;
}

}  // namespace icgm
