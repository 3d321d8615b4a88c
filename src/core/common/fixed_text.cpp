#include "core/common/fixed_text.h"

#include <cstdio>

namespace icgm {

std::string FormatFixed(double value, int decimals) {
  char text[64];
  std::snprintf(text, sizeof(text), "%.*f", decimals, value);
  return text;
}

}  // namespace icgm
