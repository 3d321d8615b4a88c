// A number as text with a fixed number of decimals ("%.*f"), for reasons and messages.
#pragma once

#include <string>

namespace icgm {

std::string FormatFixed(double value, int decimals);

}  // namespace icgm
