#pragma once
// Strict YAML reading for config and world files: every value is read through a
// YamlReader, which remembers the file and key path so errors name both, and `finish()`
// rejects keys that nothing read (typos must not be silently ignored).

#include <yaml-cpp/yaml.h>

#include <cstdint>
#include <set>
#include <string>
#include <vector>

#include "canopy/common/enum_names.h"
#include "canopy/common/error.h"

namespace canopy {

/// Largest YAML input (world, settings, experiment files): these are hand-written files.
constexpr std::uintmax_t kMaxYamlFileBytes = std::uintmax_t(4) << 20;
/// Most nodes a YAML document may have once its aliases are expanded (a few hundred in
/// canopy's own files): nested aliases can otherwise describe billions of nodes in a few
/// hundred bytes.
constexpr std::uint64_t kMaxYamlNodes = 100000;

/// Reads one YAML mapping with key tracking. Throws InputError on any problem.
class YamlReader {
 public:
  YamlReader(YAML::Node node, std::string file, std::string path);

  /// Loads and parses `file`; throws InputError when it is missing, a folder, empty, larger
  /// than kMaxYamlFileBytes, malformed, expands (through aliases) to more than kMaxYamlNodes
  /// nodes, or has a repeated key in any mapping (the message names both lines).
  static YamlReader load_file(const std::string& file);
  /// Parses YAML text (for tests and embedded configs); `name` stands in for the file.
  static YamlReader load_string(const std::string& text, const std::string& name);

  bool has(const std::string& key) const;
  /// Value of `key` converted to T, or `fallback` when absent.
  template <typename T>
  T get(const std::string& key, const T& fallback);
  /// Value of `key` converted to T; throws when absent.
  template <typename T>
  T require(const std::string& key);
  /// A named choice (a string from `names`), or `fallback` when absent; fails naming the key
  /// and the valid names otherwise.
  template <typename E, std::size_t N>
  E get_choice(const std::string& key, E fallback, const EnumName<E> (&names)[N]);
  /// Nested mapping under `key` (an empty mapping when absent).
  YamlReader child(const std::string& key);
  /// Throws InputError naming the first key that no get/require/child call read.
  void finish() const;
  /// Moves the value of `old_key` to `new_key` (a key read under its former name); false when
  /// `old_key` is absent.
  bool rename(const std::string& old_key, const std::string& new_key);

  /// Throws InputError "<file>: key '<path.key>': value '<value>' <problem>".
  [[noreturn]] void fail(const std::string& key, const std::string& problem) const;
  /// fail() unless `ok`.
  void check(bool ok, const std::string& key, const std::string& problem) const {
    if (!ok) fail(key, problem);
  }

  const std::string& file() const { return file_; }
  std::string key_path(const std::string& key) const;
  std::string value_text(const std::string& key) const;
  /// True when `key` holds a scalar (not a mapping or list).
  bool value_is_scalar(const std::string& key) const;

 private:
  YAML::Node node_;
  std::string file_;
  std::string path_;
  mutable std::set<std::string> read_;
};

template <typename T>
T YamlReader::get(const std::string& key, const T& fallback) {
  if (!has(key)) {
    read_.insert(key);
    return fallback;
  }
  return require<T>(key);
}

template <typename T>
T YamlReader::require(const std::string& key) {
  read_.insert(key);
  if (!has(key)) throw InputError(file_ + ": missing key '" + key_path(key) + "'");
  try {
    return node_[key].template as<T>();
  } catch (const YAML::Exception&) {
    fail(key, "has the wrong type");
  }
}

template <typename E, std::size_t N>
E YamlReader::get_choice(const std::string& key, E fallback, const EnumName<E> (&names)[N]) {
  const std::string s = get<std::string>(key, enum_name(names, fallback));
  const E* v = find_enum(names, s);
  if (!v) fail(key, "must be one of: " + enum_name_list(names));
  return *v;
}

/// A finite number (or `fallback` when absent); fails naming the key otherwise.
inline double get_finite(YamlReader& y, const std::string& key, double fallback) {
  const double v = y.get(key, fallback);
  y.check(v == v && v - v == 0.0, key, "must be a finite number");
  return v;
}
/// A finite number > 0.
inline double get_positive(YamlReader& y, const std::string& key, double fallback) {
  const double v = get_finite(y, key, fallback);
  y.check(v > 0.0, key, "must be > 0");
  return v;
}
/// An integer in [lo, hi].
inline int get_count(YamlReader& y, const std::string& key, int fallback, int lo, int hi) {
  const int v = y.get(key, fallback);
  y.check(v >= lo && v <= hi, key, "must be in [" + std::to_string(lo) + ", " + std::to_string(hi) + "]");
  return v;
}

}  // namespace canopy
