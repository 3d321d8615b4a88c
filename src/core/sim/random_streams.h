// Independent random streams per purpose (and per frame), so that e.g. adding pedestrians does
// not change the furniture and frame i looks the same whatever order frames are rendered in.
// Simulator and ClosedLoopSimulator draw from the same streams, so one seed builds one world.
#pragma once

#include <cstdint>

namespace icgm::sim {

enum class Stream : uint64_t {
  kWorld = 1,
  kCrowd = 2,
  kOdometry = 3,
  kFrame = 4,
  kHandheld = 5,
  kDrive = 6,  // actuation noise of the closed-loop robot
  kScan = 7,   // range noise of the closed-loop robot's planar scanner
};

inline uint64_t StreamSeed(int seed, Stream stream, uint64_t index = 0) {
  // SplitMix64 finalizer over the combined key.
  uint64_t z = static_cast<uint64_t>(seed) * 0x9E3779B97F4A7C15ull +
               static_cast<uint64_t>(stream) * 0xBF58476D1CE4E5B9ull +
               index * 0x94D049BB133111EBull;
  z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
  z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
  return z ^ (z >> 31);
}

}  // namespace icgm::sim
