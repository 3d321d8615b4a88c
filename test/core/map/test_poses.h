// Shared helpers for the map tests: random poses and a pose comparison.
#pragma once

#include <random>

#include "core/common/pose.h"
#include "core/map/se3_geodesic.h"

namespace icgm::test {

inline Vec6 RandomTwist(std::mt19937* rng, double sigma_t, double sigma_r) {
  std::normal_distribution<double> nt(0.0, sigma_t);
  std::normal_distribution<double> nr(0.0, sigma_r);
  Vec6 v;
  v << nt(*rng), nt(*rng), nt(*rng), nr(*rng), nr(*rng), nr(*rng);
  return v;
}

// Twist norm of a^-1 b: zero iff the poses are equal.
inline double PoseDistance(const Pose3& a, const Pose3& b) {
  return GeodesicLog(a.inverse() * b).norm();
}

}  // namespace icgm::test
