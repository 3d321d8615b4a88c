// Per-pixel policy for the two depth encodings the core accepts (in the spirit of
// depth_image_proc's depth_traits.h): integer depth scaled by a factor (uint16, e.g. mm or
// TUM's 1/5000 m) and float depth already in metres. One conversion loop is written once
// against this interface.
#pragma once

#include <cmath>
#include <cstdint>

namespace icgm {

template <typename T>
struct DepthTraits;

template <>
struct DepthTraits<uint16_t> {
  // 0 is the sensor's "no measurement".
  static bool Valid(uint16_t raw) { return raw != 0; }
  static float ToMetres(uint16_t raw, double depth_scale) {
    return static_cast<float>(raw / depth_scale);
  }
};

template <>
struct DepthTraits<float> {
  // NaN, +-inf, 0 and negative values carry no measurement.
  static bool Valid(float raw) { return std::isfinite(raw) && raw > 0.0f; }
  static float ToMetres(float raw, double /*depth_scale*/) { return raw; }
};

}  // namespace icgm
