// The spellings of an option's choices, in one table per enum class. Each enum of choices
// specialises EnumNames next to its definition:
//
//   enum class Loss { kHuber, kCauchy, kNone };
//   template <>
//   struct EnumNames<Loss> {
//     static constexpr EnumName<Loss> kNames[] = {
//         {Loss::kHuber, "huber"}, {Loss::kCauchy, "cauchy"}, {Loss::kNone, "none"}};
//   };
//
// and the generic functions below convert both ways, so the YAML reader
// (OptionReader::ReadEnum), the tools' command lines and the log messages spell every choice
// the same way and list the same allowed values when one is misspelt.
#pragma once

#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace icgm {

template <typename E>
struct EnumName {
  E value;
  const char* name;
};

// Specialised per enum with `static constexpr EnumName<E> kNames[]` (every value once).
template <typename E>
struct EnumNames;

// The spelling of `value` ("?" for a value missing from the table, which is a bug).
template <typename E>
const char* NameOf(E value) {
  for (const EnumName<E>& n : EnumNames<E>::kNames) {
    if (n.value == value) return n.name;
  }
  return "?";
}

// The value spelt `text`, or nullopt.
template <typename E>
std::optional<E> ParseEnum(std::string_view text) {
  for (const EnumName<E>& n : EnumNames<E>::kNames) {
    if (text == n.name) return n.value;
  }
  return std::nullopt;
}

// Every spelling, in table order.
template <typename E>
std::vector<std::string> EnumChoices() {
  std::vector<std::string> out;
  for (const EnumName<E>& n : EnumNames<E>::kNames) out.emplace_back(n.name);
  return out;
}

// "'x' is not one of {a, b, c}": the reason a spelling is refused.
std::string NotOneOf(std::string_view text, const std::vector<std::string>& choices);

template <typename E>
std::string NotOneOf(std::string_view text) {
  return NotOneOf(text, EnumChoices<E>());
}

}  // namespace icgm
