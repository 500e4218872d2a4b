#pragma once
// The vocabulary of every params archive (params.h): what a number setting must satisfy
// (Limits, built by limits::in(lo, hi), limits::positive(), ...) and how a setting's value reads
// as text in messages, the reference and YAML (params_detail: shortest exact numbers, lists and
// maps on one line).

#include <yaml-cpp/yaml.h>

#include <cmath>
#include <cstddef>
#include <limits>
#include <map>
#include <string>
#include <type_traits>
#include <vector>

namespace canopy {

/// The most numbers a list setting holds (a stop list for a 1,000-plant row); lists whose
/// entries multiply the work (candidate radii) declare a lower limit of their own.
constexpr std::size_t kMaxListEntries = 1000;

/// What a number must satisfy. Numbers are always finite.
struct Limits {
  double lo = -std::numeric_limits<double>::infinity();
  double hi = std::numeric_limits<double>::infinity();
  bool lo_open = false, hi_open = false;

  bool ok(double v) const {
    if (!std::isfinite(v)) return false;
    if (lo_open ? !(v > lo) : !(v >= lo)) return false;
    if (hi_open ? !(v < hi) : !(v <= hi)) return false;
    return true;
  }
  /// "must be > 0", "must be in [0, 1]", "must be a finite number", ...
  std::string text() const;
};

namespace limits {
inline Limits finite() { return {}; }
inline Limits positive() { return {0.0, std::numeric_limits<double>::infinity(), true, false}; }
inline Limits non_negative() { return {0.0, std::numeric_limits<double>::infinity(), false, false}; }
inline Limits negative() { return {-std::numeric_limits<double>::infinity(), 0.0, false, true}; }
/// [lo, hi].
inline Limits in(double lo, double hi) { return {lo, hi, false, false}; }
/// (lo, hi].
inline Limits above_up_to(double lo, double hi) { return {lo, hi, true, false}; }
/// [lo, hi).
inline Limits from_below(double lo, double hi) { return {lo, hi, false, true}; }
/// (lo, hi).
inline Limits open(double lo, double hi) { return {lo, hi, true, true}; }
inline Limits at_least(double lo) { return {lo, std::numeric_limits<double>::infinity(), false, false}; }
}  // namespace limits

namespace params_detail {
template <typename T>
constexpr bool is_number =
    std::is_arithmetic_v<T> && !std::is_same_v<T, bool>;  // int, unsigned, float, double, ...

template <typename T>
struct is_vector : std::false_type {};
template <typename U>
struct is_vector<std::vector<U>> : std::true_type {};
template <typename T>
struct is_map : std::false_type {};
template <typename K, typename V>
struct is_map<std::map<K, V>> : std::true_type {};
/// "[min, max] of numbers": what a tuple must be, for messages and the reference.
std::string tuple_text(const char* shape, bool whole, const Limits& each);

/// The shortest decimal text that reads back to exactly `v` ("0.015", not "0.014999999999999999").
std::string shortest(double v);
/// The same for a float: the shortest text whose double, cast to float, is `v` ("-0.1").
std::string shortest(float v);

template <typename T>
std::string value_text(const T& v) {
  if constexpr (std::is_same_v<T, bool>) return v ? "true" : "false";
  else if constexpr (std::is_same_v<T, std::string>) return v;
  else if constexpr (std::is_floating_point_v<T>) return shortest(v);
  else if constexpr (is_vector<T>::value) {  // on one line, as YAML: [a, b]
    std::string s;
    for (const auto& x : v) s += (s.empty() ? "" : ", ") + value_text(x);
    return "[" + s + "]";
  } else if constexpr (is_map<T>::value) {  // {key: value, ...}
    std::string s;
    for (const auto& [k, x] : v) s += (s.empty() ? "" : ", ") + value_text(k) + ": " + value_text(x);
    return "{" + s + "}";
  } else return std::to_string(v);
}
std::string join(const std::vector<std::string>& names);
/// A YAML scalar of a number: floating point as its shortest exact text.
template <typename T>
YAML::Node number_node(const T& v) {
  if constexpr (std::is_floating_point_v<T>) return YAML::Node(shortest(v));
  else return YAML::Node(v);
}
}  // namespace params_detail

}  // namespace canopy
