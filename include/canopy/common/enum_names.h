#pragma once
// Named protocol choices: one table of (value, name) per enum serves to_string, parsing
// (CLI flags, saved settings) and strict YAML reading (YamlReader::get_choice), so the valid
// names are written once and every error lists them.

#include <cstddef>
#include <string>

#include "canopy/common/error.h"

namespace canopy {

template <typename E>
struct EnumName {
  E value;
  const char* name;
};

/// "a, b, c": the names of a table.
template <typename E, std::size_t N>
std::string enum_name_list(const EnumName<E> (&names)[N]) {
  std::string s;
  for (const auto& n : names) s += (s.empty() ? "" : ", ") + std::string(n.name);
  return s;
}

/// The name of `value` ("?" when the table lacks it).
template <typename E, std::size_t N>
const char* enum_name(const EnumName<E> (&names)[N], E value) {
  for (const auto& n : names)
    if (n.value == value) return n.name;
  return "?";
}

/// The value named `s`, or nullptr.
template <typename E, std::size_t N>
const E* find_enum(const EnumName<E> (&names)[N], const std::string& s) {
  for (const auto& n : names)
    if (s == n.name) return &n.value;
  return nullptr;
}

/// The value named `s`; throws InputError "<where>: unknown <what> '<s>' (valid: ...)".
template <typename E, std::size_t N>
E enum_from_name(const EnumName<E> (&names)[N], const std::string& s, const std::string& where,
                 const std::string& what) {
  if (const E* v = find_enum(names, s)) return *v;
  throw InputError(where + ": unknown " + what + " '" + s + "' (valid: " + enum_name_list(names) + ")");
}

}  // namespace canopy
