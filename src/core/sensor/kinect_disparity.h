// The Kinect v1's raw 11-bit depth (the disparity its IR camera measures, as libfreenect's
// FREENECT_DEPTH_11BIT mode and fakenect recordings hold it) and millimetres of depth.
// Model: inverse depth linear in the raw value, 1 / z[m] = a * raw + b, with the widely used
// calibration of a Kinect v1 (a = -0.0030711016, b = 3.3309495161; N. Burrus, "Kinect
// calibration", 2011): raw 0 is 0.30 m, raw 1000 is 3.6 m; raw 2047 means no depth. Depth is
// kept within [kKinectMinDepthMm, kKinectMaxDepthMm]; outside it (and raw 2047) is 0, no depth.
#pragma once

#include <cstddef>
#include <cstdint>

namespace icgm {

inline constexpr uint16_t kKinectRawNoDepth = 2047;
inline constexpr uint16_t kKinectMinDepthMm = 300;
inline constexpr uint16_t kKinectMaxDepthMm = 10000;

// Millimetres (rounded) of a raw value; 0 for no depth.
uint16_t KinectRawToMm(uint16_t raw);
// The raw value whose depth is nearest to `mm`; kKinectRawNoDepth for 0 or a depth outside
// the range above.
uint16_t KinectMmToRaw(uint16_t mm);
// KinectRawToMm over n values (a table lookup).
void KinectRawToMm(const uint16_t* raw, uint16_t* mm, size_t n);

}  // namespace icgm
