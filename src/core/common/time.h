// Core time type: a timestamp in integer nanoseconds since an arbitrary epoch
// (the sensor's or the bag's). ROS conversions live in src/ros_bridge only.
#pragma once

#include <cstdint>
#include <string>

namespace icgm {

class Time {
 public:
  constexpr Time() = default;
  static constexpr Time FromNanoseconds(int64_t ns) { return Time(ns); }
  static Time FromSeconds(double s);
  // Parses "1305031102.175304" exactly (no double rounding), as in TUM files.
  static bool Parse(const std::string& text, Time* out);

  constexpr int64_t nanoseconds() const { return ns_; }
  double seconds() const { return static_cast<double>(ns_) * 1e-9; }
  // Fixed-point "sec.nsec" text with 6 decimals (TUM format).
  std::string ToString(int decimals = 6) const;

  constexpr bool operator<(const Time& o) const { return ns_ < o.ns_; }
  constexpr bool operator<=(const Time& o) const { return ns_ <= o.ns_; }
  constexpr bool operator>(const Time& o) const { return ns_ > o.ns_; }
  constexpr bool operator>=(const Time& o) const { return ns_ >= o.ns_; }
  constexpr bool operator==(const Time& o) const { return ns_ == o.ns_; }
  constexpr bool operator!=(const Time& o) const { return ns_ != o.ns_; }

 private:
  constexpr explicit Time(int64_t ns) : ns_(ns) {}
  int64_t ns_ = 0;
};

// Signed difference a - b in seconds.
inline double DurationSeconds(const Time& a, const Time& b) {
  return static_cast<double>(a.nanoseconds() - b.nanoseconds()) * 1e-9;
}

}  // namespace icgm
