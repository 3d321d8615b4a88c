#include "core/common/enum_names.h"

namespace icgm {

std::string NotOneOf(std::string_view text, const std::vector<std::string>& choices) {
  std::string s = "'" + std::string(text) + "' is not one of {";
  for (size_t i = 0; i < choices.size(); ++i) s += (i ? ", " : "") + choices[i];
  return s + "}";
}

}  // namespace icgm
