#pragma once
// Each parameter struct states its keys once, in a visit() function (after Drake's
// Serialize(Archive*) and nvblox's Param<T>::Description), and that one list serves:
//  - reading YAML strictly (YamlIn: absent keys keep their values, unknown keys and bad values
//    are errors naming the file, the key path and the value),
//  - writing YAML (YamlOut: every key, in the order visited, floats as the doubles they are)
//    and JSON (JsonOut: numbers as the C++ types they are, for result records),
//  - validating a struct built in code (validate_params),
//  - equality (same_params), the reference of every setting (describe_params) and the
//    commented settings files of configs/ (YamlDoc, params_yaml_doc).
//
// A struct's visit names each field with its limits and a line of help:
//
//   template <class Archive>
//   void visit(Archive& a) {
//     a("resolution_m", resolution_m, limits::in(0.001, 1.0), "Voxel edge [m]");
//     a("prune", prune, "Collapse eight identical children after each scan");
//     a.choice("noise", noise, kNoiseModelNames, "What one P_gt draw flips");
//     a.section("cluster", cluster, "Fruit clustering");
//     a.tuple("height_m", {&min_m, &max_m}, "[min, max]", limits::positive(), "Plant height [m]");
//     a.check(max_m >= min_m, "max_m", "must be >= min_m");   // across fields, after both
//     a.renamed("planner", "ours");   // a section's former key, still read (a warning names it)
//   }

#include <nlohmann/json.hpp>
#include <yaml-cpp/yaml.h>

#include <cmath>
#include <cstdint>
#include <initializer_list>
#include <limits>
#include <map>
#include <string>
#include <type_traits>
#include <vector>

#include "canopy/common/enum_names.h"
#include "canopy/common/error.h"
#include "canopy/common/yaml_reader.h"

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

// --- YAML and JSON out ---------------------------------------------------------------------

namespace params_detail {
// How an output archive builds its document: YAML numbers in their shortest exact text (a
// setting written and read back is the same double), JSON numbers as the C++ values.
struct YamlNodes {
  using Node = YAML::Node;
  static Node map() { return Node(YAML::NodeType::Map); }
  static Node list() { return Node(YAML::NodeType::Sequence); }
  template <typename T>
  static Node number(const T& v) { return number_node(v); }
  template <typename T>
  static Node value(const T& v) { return Node(v); }
  static void push(Node& list, const Node& item) { list.push_back(item); }
};
struct JsonNodes {
  using Node = nlohmann::json;
  static Node map() { return Node::object(); }
  static Node list() { return Node::array(); }
  template <typename T>
  static Node number(const T& v) { return Node(v); }
  template <typename T>
  static Node value(const T& v) { return Node(v); }
  static void push(Node& list, const Node& item) { list.push_back(item); }
};
}  // namespace params_detail

/// Writes every key of a struct, in visiting order, into one document of `Nodes`' kind: the
/// one output archive behind YamlOut (settings.yaml, docs) and JsonOut (records, JSON files).
template <class Nodes>
class OutArchive {
 public:
  typename Nodes::Node node = Nodes::map();

  template <typename T>
  void operator()(const char* key, const T& value, const char* /*help*/) {
    node[key] = Nodes::value(value);
  }
  template <typename T>
  void operator()(const char* key, const T& value, const Limits&, const char* /*help*/) {
    node[key] = Nodes::number(value);
  }
  template <typename T>
  void operator()(const char* key, const std::vector<T>& value, const Limits&, const char* /*help*/) {
    typename Nodes::Node s = Nodes::list();
    for (const T& x : value) Nodes::push(s, Nodes::number(x));
    node[key] = s;
  }
  template <typename T>
  void tuple(const char* key, std::initializer_list<T*> parts, const char*, const Limits&, const char* /*help*/) {
    typename Nodes::Node s = Nodes::list();
    for (const T* p : parts) Nodes::push(s, Nodes::number(*p));
    node[key] = s;
  }
  void required(const char* key, const std::string& value, const char* /*help*/) { node[key] = Nodes::value(value); }
  template <typename E, std::size_t N>
  void choice(const char* key, const E& value, const EnumName<E> (&names)[N], const char* /*help*/) {
    node[key] = Nodes::value(std::string(enum_name(names, value)));
  }
  void one_of(const char* key, const std::string& value, const std::vector<std::string>&, const char* /*help*/) {
    node[key] = Nodes::value(value);
  }
  template <typename S>
  void section(const char* key, const S& s, const char* /*help*/ = "") {
    OutArchive out;
    const_cast<S&>(s).visit(out);
    node[key] = out.node;
  }
  template <typename S>
  void list(const char* key, const std::vector<S>& items, const char* /*help*/) {
    typename Nodes::Node seq = Nodes::list();
    for (const S& s : items) {
      OutArchive out;
      const_cast<S&>(s).visit(out);
      Nodes::push(seq, out.node);
    }
    node[key] = seq;
  }
  void renamed(const char*, const char*) {}
  void check(bool, const char*, const std::string&) {}
};

/// Writes every key of a struct as YAML.
using YamlOut = OutArchive<params_detail::YamlNodes>;
/// Writes every key of a struct as JSON: numbers keep their C++ type (an int stays an
/// integer, a double a double), so a record reads as the struct's own values.
using JsonOut = OutArchive<params_detail::JsonNodes>;

// --- Validation of a struct built in code ---------------------------------------------------

/// Checks every field's limits and every cross-field check; the first failure throws
/// InputError "<where>: <key path> = <value> <problem>".
class Validate {
 public:
  explicit Validate(std::string where, std::string path = "") : where_(std::move(where)), path_(std::move(path)) {}

  template <typename T>
  void operator()(const char*, const T&, const char*) {}
  template <typename T>
  void operator()(const char* key, const T& value, const Limits& lim, const char*) {
    if (!lim.ok(double(value))) fail(key, params_detail::value_text(value), lim.text());
  }
  template <typename T>
  void operator()(const char* key, const std::vector<T>& value, const Limits& each, const char*) {
    for (const T& x : value)
      if (!each.ok(double(x))) fail(key, params_detail::value_text(x), "holds a value that " + each.text());
  }
  template <typename T>
  void tuple(const char* key, std::initializer_list<T*> parts, const char* shape, const Limits& each, const char*) {
    std::vector<T> v;
    for (const T* p : parts) v.push_back(*p);
    for (const T& x : v)
      if (!each.ok(double(x)))
        fail(key, params_detail::value_text(v), "must be " + params_detail::tuple_text(shape, std::is_integral_v<T>, each));
  }
  void required(const char* key, const std::string& value, const char*) {
    if (value.empty()) fail(key, value, "is missing");
  }
  template <typename E, std::size_t N>
  void choice(const char*, const E&, const EnumName<E> (&)[N], const char*) {}
  void one_of(const char* key, const std::string& value, const std::vector<std::string>& names, const char*) {
    for (const auto& n : names)
      if (n == value) return;
    fail(key, value, "must be one of: " + params_detail::join(names));
  }
  template <typename S>
  void section(const char* key, const S& s, const char* = "") {
    Validate v(where_, path(key));
    const_cast<S&>(s).visit(v);
  }
  template <typename S>
  void list(const char* key, const std::vector<S>& items, const char*) {
    for (std::size_t i = 0; i < items.size(); ++i) {
      Validate v(where_, path(key) + "[" + std::to_string(i) + "]");
      const_cast<S&>(items[i]).visit(v);
    }
  }
  void renamed(const char*, const char*) {}
  void check(bool ok, const char* key, const std::string& problem) {
    if (!ok) fail(key, "", problem);
  }

 private:
  std::string path(const char* key) const { return path_.empty() ? key : path_ + "." + key; }
  [[noreturn]] void fail(const char* key, const std::string& value, const std::string& problem) const {
    throw InputError(where_ + ": " + path(key) + (value.empty() ? "" : " = " + value) + " " + problem);
  }
  std::string where_, path_;
};

// --- The reference of every setting ---------------------------------------------------------

/// One setting: its key path, default (as YAML), what it must be and what it is for.
struct ParamDescription {
  std::string key, value, limits, help;
};

/// Lists every key of a struct with its value, limits and help.
class Describe {
 public:
  explicit Describe(std::vector<ParamDescription>* out, std::string path = "") : out_(out), path_(std::move(path)) {}

  template <typename T>
  void operator()(const char* key, const T& value, const char* help) {
    if constexpr (std::is_same_v<T, bool>) add(key, params_detail::value_text(value), "true or false", help);
    else add(key, params_detail::value_text(value), "", help);
  }
  template <typename T>
  void operator()(const char* key, const T& value, const Limits& lim, const char* help) {
    add(key, params_detail::value_text(value), lim.text(), help);
  }
  template <typename T>
  void operator()(const char* key, const std::vector<T>& value, const Limits& each, const char* help) {
    YamlOut o;
    o(key, value, each, help);
    YAML::Emitter e;
    e << YAML::Flow << o.node[key];
    add(key, e.c_str(), "each " + each.text(), help);
  }
  template <typename T>
  void tuple(const char* key, std::initializer_list<T*> parts, const char* shape, const Limits& each, const char* help) {
    std::vector<T> v;
    for (const T* p : parts) v.push_back(*p);
    add(key, params_detail::value_text(v), params_detail::tuple_text(shape, std::is_integral_v<T>, each), help);
  }
  void required(const char* key, const std::string& value, const char* help) { add(key, value, "required", help); }
  template <typename E, std::size_t N>
  void choice(const char* key, const E& value, const EnumName<E> (&names)[N], const char* help) {
    add(key, enum_name(names, value), "one of: " + enum_name_list(names), help);
  }
  void one_of(const char* key, const std::string& value, const std::vector<std::string>& names, const char* help) {
    add(key, value, "one of: " + params_detail::join(names), help);
  }
  template <typename S>
  void section(const char* key, const S& s, const char* = "") {
    Describe d(out_, path(key));
    const_cast<S&>(s).visit(d);
  }
  template <typename S>
  void list(const char* key, const std::vector<S>& items, const char* help) {
    YamlOut o;
    o.list(key, items, help);
    YAML::Emitter e;
    e << YAML::Flow << o.node[key];
    add(key, e.c_str(), "a list", help);
  }
  void renamed(const char*, const char*) {}
  void check(bool, const char*, const std::string&) {}

 private:
  std::string path(const char* key) const { return path_.empty() ? key : path_ + "." + key; }
  void add(const char* key, std::string value, std::string lim, const char* help) {
    out_->push_back({path(key), std::move(value), std::move(lim), help ? help : ""});
  }
  std::vector<ParamDescription>* out_;
  std::string path_;
};

// --- Commented YAML: the settings files ------------------------------------------------------

/// Writes a struct as YAML text with each key's help as a comment (a section's beside its
/// key): the settings files of configs/ are this archive's output, and a test holds them to it.
class YamlDoc {
 public:
  explicit YamlDoc(int indent = 0) : indent_(indent) {}
  std::string text;

  template <typename T>
  void operator()(const char* key, const T& value, const char* help) {
    YamlOut o;
    o(key, value, help);
    line(key, flow(o.node[key]), help);
  }
  template <typename T>
  void operator()(const char* key, const T& value, const Limits& lim, const char* help) {
    YamlOut o;
    o(key, value, lim, help);
    line(key, flow(o.node[key]), help);
  }
  template <typename T>
  void tuple(const char* key, std::initializer_list<T*> parts, const char* shape, const Limits& each, const char* help) {
    YamlOut o;
    o.tuple(key, parts, shape, each, help);
    line(key, flow(o.node[key]), help);
  }
  void required(const char* key, const std::string& value, const char* help) { (*this)(key, value, help); }
  template <typename E, std::size_t N>
  void choice(const char* key, const E& value, const EnumName<E> (&names)[N], const char* help) {
    line(key, enum_name(names, value), std::string(help) + "; one of: " + enum_name_list(names));
  }
  void one_of(const char* key, const std::string& value, const std::vector<std::string>& names, const char* help) {
    line(key, flow(YAML::Node(value)), std::string(help) + "; one of: " + params_detail::join(names));
  }
  template <typename S>
  void section(const char* key, const S& s, const char* help = "") {
    line(key, "", help);
    YamlDoc d(indent_ + 2);
    const_cast<S&>(s).visit(d);
    text += d.text;
  }
  template <typename S>
  void list(const char* key, const std::vector<S>& items, const char* help) {
    YamlOut o;
    o.list(key, items, help);
    line(key, flow(o.node[key]), help);
  }
  void renamed(const char*, const char*) {}
  void check(bool, const char*, const std::string&) {}

 private:
  static std::string flow(const YAML::Node& node);
  /// "<indent>key: value" and, from column 32 (or two spaces after), "# help".
  void line(const char* key, const std::string& value, const std::string& help);
  int indent_;
};

// --- Entry points --------------------------------------------------------------------------

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
/// `p` as a YAML mapping.
template <typename P>
YAML::Node params_to_yaml(const P& p) {
  YamlOut out;
  const_cast<P&>(p).visit(out);
  return out.node;
}
/// `p` as a JSON object (numbers as their C++ types).
template <typename P>
nlohmann::json params_to_json(const P& p) {
  JsonOut out;
  const_cast<P&>(p).visit(out);
  return out.node;
}
/// The reference table of settings in Markdown ("| key | default | must be | meaning |"), as
/// docs/settings.md and docs/plants.md hold it.
std::string params_markdown(const std::vector<ParamDescription>& rows);
/// YAML text of a node with doubles at full precision (what is saved reads back exactly).
std::string yaml_text(const YAML::Node& node);
/// A YAML tree as JSON, for result records that quote settings: scalars become booleans,
/// integers or numbers where they read as one, strings otherwise.
nlohmann::json yaml_to_json(const YAML::Node& node);
/// Throws InputError naming `where`, the key and the value when `p` breaks a limit or check.
template <typename P>
void validate_params(const P& p, const std::string& where) {
  Validate v(where);
  const_cast<P&>(p).visit(v);
}
/// `p` as commented YAML (YamlDoc): the text of a settings file, after `header` (comment lines).
template <typename P>
std::string params_yaml_doc(const P& p, const std::string& header = "") {
  YamlDoc d;
  const_cast<P&>(p).visit(d);
  return header + d.text;
}
/// The one-line warning for a key read under its former name (YamlIn::renamed, a --set of the
/// old key path): "<where>: key '<old_path>' is now '<new_path>'; read as such (rename it)".
void warn_renamed_key(const std::string& where, const std::string& old_path, const std::string& new_path);
/// True when every key has the same value.
template <typename P>
bool same_params(const P& a, const P& b) {
  return yaml_text(params_to_yaml(a)) == yaml_text(params_to_yaml(b));
}
/// Every setting of `p` (key paths under `prefix`).
template <typename P>
std::vector<ParamDescription> describe_params(const P& p, const std::string& prefix = "") {
  std::vector<ParamDescription> out;
  Describe d(&out, prefix);
  const_cast<P&>(p).visit(d);
  return out;
}

}  // namespace canopy
