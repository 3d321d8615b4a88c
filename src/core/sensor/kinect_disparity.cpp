#include "core/sensor/kinect_disparity.h"

#include <array>
#include <cmath>

namespace icgm {
namespace {

constexpr double kA = -0.0030711016;  // 1/m per raw step
constexpr double kB = 3.3309495161;   // 1/m

// Raw -> mm for every 11-bit value; 0 where the model gives no depth in range.
const std::array<uint16_t, 2048>& Table() {
  static const std::array<uint16_t, 2048> table = [] {
    std::array<uint16_t, 2048> t{};
    for (int raw = 0; raw < 2048; ++raw) {
      const double inverse = kA * raw + kB;
      if (raw == kKinectRawNoDepth || inverse <= 0.0) continue;
      const double mm = std::round(1000.0 / inverse);
      if (mm >= kKinectMinDepthMm && mm <= kKinectMaxDepthMm) t[raw] = static_cast<uint16_t>(mm);
    }
    return t;
  }();
  return table;
}

}  // namespace

uint16_t KinectRawToMm(uint16_t raw) { return raw < 2048 ? Table()[raw] : 0; }

uint16_t KinectMmToRaw(uint16_t mm) {
  if (mm < kKinectMinDepthMm || mm > kKinectMaxDepthMm) return kKinectRawNoDepth;
  // The model's inverse, then the neighbouring raw values whose rounded depth is nearest.
  const double raw = (1000.0 / mm - kB) / kA;
  const int guess = static_cast<int>(std::lround(raw));
  uint16_t best = kKinectRawNoDepth;
  int best_error = 1 << 30;
  for (int r = guess - 1; r <= guess + 1; ++r) {
    if (r < 0 || r >= kKinectRawNoDepth || Table()[r] == 0) continue;
    const int error = std::abs(static_cast<int>(Table()[r]) - static_cast<int>(mm));
    if (error < best_error) {
      best_error = error;
      best = static_cast<uint16_t>(r);
    }
  }
  return best;
}

void KinectRawToMm(const uint16_t* raw, uint16_t* mm, size_t n) {
  const std::array<uint16_t, 2048>& t = Table();
  for (size_t i = 0; i < n; ++i) mm[i] = raw[i] < 2048 ? t[raw[i]] : 0;
}

}  // namespace icgm
