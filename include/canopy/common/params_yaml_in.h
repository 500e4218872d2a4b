#pragma once
// Reading a params struct from YAML strictly (params.h): YamlIn, the archive a struct's visit()
// reads its keys with (absent keys keep their values; unknown keys and bad values are errors
// naming the file, the key path and the value), and the entry points read_params,
// params_from_yaml and load_params.

#include <cstdint>
#include <initializer_list>
#include <map>
#include <string>
#include <type_traits>
#include <vector>

#include "canopy/common/enum_names.h"
#include "canopy/common/error.h"
#include "canopy/common/params_limits.h"
#include "canopy/common/yaml_reader.h"

namespace canopy {

// --- YAML in -------------------------------------------------------------------------------

/// Reads a struct's keys from one YAML mapping over its current values. Sections given as a
/// file name (a string) are read from that file when `section_files` is set (relative to the
/// folder of the file that names them): the settings bundle's component files.
class YamlIn {
 public:
  explicit YamlIn(YamlReader& reader, bool section_files = false, std::string dir = "")
      : y_(reader), section_files_(section_files), dir_(std::move(dir)) {}

  template <typename T>
  void operator()(const char* key, T& value, const char* /*help*/) {
    static_assert(!params_detail::is_number<T>, "numbers need limits: a(key, value, limits::..., help)");
    read(key, value);
  }
  template <typename T>
  void operator()(const char* key, T& value, const Limits& lim, const char* /*help*/) {
    static_assert(params_detail::is_number<T>, "limits apply to numbers");
    if (!y_.has(key)) {
      y_.get<std::string>(key, "");  // marks it read
      return;
    }
    T v{};
    if constexpr (std::is_floating_point_v<T>) {
      const double d = y_.require<double>(key);
      y_.check(lim.ok(d), key, lim.text());
      v = static_cast<T>(d);
    } else {
      // Integers: the text must be a whole number in range (yaml-cpp wraps some overflows).
      y_.require<YAML::Node>(key);  // marks the key read
      const std::string text = y_.value_text(key);
      long double d = 0;
      std::size_t used = 0;
      try {
        d = std::stold(text, &used);
      } catch (const std::exception&) {
        y_.fail(key, "must be a whole number");
      }
      y_.check(used == text.size() && d == std::floor(d), key, "must be a whole number");
      y_.check(d >= static_cast<long double>(std::numeric_limits<T>::lowest()) &&
                   d <= static_cast<long double>(std::numeric_limits<T>::max()) && lim.ok(double(d)),
               key, lim.text());
      v = static_cast<T>(d);
    }
    value = v;
  }
  /// A list of numbers, each within `each`.
  template <typename T>
  void operator()(const char* key, std::vector<T>& value, const Limits& each, const char* /*help*/) {
    if (!y_.has(key)) {
      y_.get<std::string>(key, "");
      return;
    }
    const YAML::Node n = y_.require<YAML::Node>(key);
    y_.check(n.IsSequence(), key, "must be a list of numbers");
    y_.check(n.size() <= kMaxListEntries, key,
             "holds " + std::to_string(n.size()) + " numbers, at most " + std::to_string(kMaxListEntries));
    std::vector<T> v;
    for (const auto& item : n) {
      double d = 0.0;
      try {
        d = item.as<double>();
      } catch (const YAML::Exception&) {
        y_.fail(key, "must be a list of numbers");
      }
      y_.check(each.ok(d), key, "holds a value that " + each.text());
      if constexpr (std::is_integral_v<T>) y_.check(d == std::floor(d), key, "must hold whole numbers");
      v.push_back(static_cast<T>(d));
    }
    value = std::move(v);
  }
  /// A fixed-length list of numbers held in separate fields (e.g. [min, max]), each within `each`.
  template <typename T>
  void tuple(const char* key, std::initializer_list<T*> parts, const char* shape, const Limits& each,
             const char* /*help*/) {
    if (!y_.has(key)) {
      y_.get<std::string>(key, "");
      return;
    }
    const YAML::Node n = y_.require<YAML::Node>(key);
    const std::string problem = "must be " + params_detail::tuple_text(shape, std::is_integral_v<T>, each);
    y_.check(n.IsSequence() && n.size() == parts.size(), key, problem);
    std::vector<T> v;
    for (const auto& item : n) {
      double d = 0.0;
      try {
        d = item.as<double>();
      } catch (const YAML::Exception&) {
        y_.fail(key, problem);
      }
      y_.check(each.ok(d), key, problem);
      if constexpr (std::is_integral_v<T>) y_.check(d == std::floor(d), key, problem);
      v.push_back(static_cast<T>(d));
    }
    std::size_t i = 0;
    for (T* p : parts) *p = v[i++];
  }
  /// A string that must be present.
  void required(const char* key, std::string& value, const char* /*help*/) { value = y_.require<std::string>(key); }
  template <typename E, std::size_t N>
  void choice(const char* key, E& value, const EnumName<E> (&names)[N], const char* /*help*/) {
    value = y_.get_choice(key, value, names);
  }
  /// A string from `names`.
  void one_of(const char* key, std::string& value, const std::vector<std::string>& names, const char* /*help*/) {
    read(key, value);
    for (const auto& n : names)
      if (n == value) return;
    y_.fail(key, "must be one of: " + params_detail::join(names));
  }
  template <typename S>
  void section(const char* key, S& s, const char* /*help*/ = "") {
    if (section_files_ && y_.has(key) && y_.value_is_scalar(key)) {
      const std::string path = resolve(y_.require<std::string>(key));
      YamlReader c = YamlReader::load_file(path);
      YamlIn in(c, false, "");
      s.visit(in);
      c.finish();
      return;
    }
    YamlReader c = y_.child(key);
    YamlIn in(c, false, "");
    s.visit(in);
    c.finish();
  }
  /// A list of structs (replaces the defaults when given; at least one item).
  template <typename S>
  void list(const char* key, std::vector<S>& items, const char* /*help*/) {
    if (!y_.has(key)) {
      y_.get<std::string>(key, "");
      return;
    }
    const YAML::Node n = y_.require<YAML::Node>(key);
    y_.check(n.IsSequence() && n.size() > 0, key, "must be a non-empty list");
    std::vector<S> out;
    for (std::size_t i = 0; i < n.size(); ++i) {
      YamlReader c(n[i], y_.file(), y_.key_path(key) + "[" + std::to_string(i) + "]");
      YamlIn in(c, false, "");
      S item{};
      item.visit(in);
      c.finish();
      out.push_back(std::move(item));
    }
    items = std::move(out);
  }
  /// `old_key` is the former name of `key`: when given (and `key` is not), it is read as `key`
  /// with a one-line deprecation warning.
  void renamed(const char* old_key, const char* key);
  void check(bool ok, const char* key, const std::string& problem) {
    if (ok) return;
    if (y_.has(key)) y_.fail(key, problem);
    // Not in the file: the default or earlier value is at fault, together with the key read.
    throw InputError(y_.file() + ": key '" + y_.key_path(key) + "' (not given) " + problem);
  }

 private:
  template <typename T>
  void read(const char* key, T& value) {
    value = y_.get<T>(key, value);
  }
  std::string resolve(const std::string& path) const;

  YamlReader& y_;
  bool section_files_;
  std::string dir_;
};

/// Reads `p`'s keys from `y` over its current values (call y.finish() after to reject
/// unknown keys at this level).
template <typename P>
void read_params(YamlReader& y, P& p) {
  YamlIn in(y);
  p.visit(in);
}
/// A struct read from `y` over `p` (defaults unless given).
template <typename P>
P params_from_yaml(YamlReader& y, P p = P{}) {
  read_params(y, p);
  return p;
}
/// A struct read from a YAML file over `p`; unknown keys are errors.
template <typename P>
P load_params(const std::string& path, P p = P{}) {
  YamlReader y = YamlReader::load_file(path);
  read_params(y, p);
  y.finish();
  return p;
}

}  // namespace canopy
