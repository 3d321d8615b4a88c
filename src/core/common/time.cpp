#include "core/common/time.h"

#include <cmath>
#include <cstdio>
#include <cstdlib>

namespace icgm {

Time Time::FromSeconds(double s) { return Time(static_cast<int64_t>(std::llround(s * 1e9))); }

bool Time::Parse(const std::string& text, Time* out) {
  if (text.empty()) return false;
  size_t i = 0;
  bool negative = false;
  if (text[0] == '-') {
    negative = true;
    i = 1;
  }
  int64_t sec = 0;
  int64_t frac = 0;
  int frac_digits = 0;
  bool any_digit = false;
  for (; i < text.size() && text[i] != '.'; ++i) {
    if (text[i] < '0' || text[i] > '9') return false;
    sec = sec * 10 + (text[i] - '0');
    any_digit = true;
  }
  if (i < text.size()) {
    for (++i; i < text.size(); ++i) {
      if (text[i] < '0' || text[i] > '9') return false;
      any_digit = true;
      if (frac_digits < 9) {
        frac = frac * 10 + (text[i] - '0');
        ++frac_digits;
      }
    }
  }
  if (!any_digit) return false;
  for (; frac_digits < 9; ++frac_digits) frac *= 10;
  const int64_t ns = sec * 1000000000LL + frac;
  *out = Time(negative ? -ns : ns);
  return true;
}

std::string Time::ToString(int decimals) const {
  const bool negative = ns_ < 0;
  const int64_t abs_ns = negative ? -ns_ : ns_;
  int64_t sec = abs_ns / 1000000000LL;
  int64_t frac = abs_ns % 1000000000LL;
  if (decimals < 0) decimals = 0;
  if (decimals > 9) decimals = 9;
  int64_t div = 1;
  for (int k = decimals; k < 9; ++k) div *= 10;
  // Round half up at the requested precision.
  int64_t scaled = (frac + div / 2) / div;
  int64_t limit = 1;
  for (int k = 0; k < decimals; ++k) limit *= 10;
  if (scaled >= limit) {
    scaled -= limit;
    ++sec;
  }
  char buf[64];
  if (decimals == 0) {
    std::snprintf(buf, sizeof(buf), "%s%lld", negative ? "-" : "", static_cast<long long>(sec));
  } else {
    std::snprintf(buf, sizeof(buf), "%s%lld.%0*lld", negative ? "-" : "",
                  static_cast<long long>(sec), decimals, static_cast<long long>(scaled));
  }
  return buf;
}

}  // namespace icgm
