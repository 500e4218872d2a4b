#pragma once
// Each parameter struct states its keys once, in a visit() function (after Drake's
// Serialize(Archive*) and nvblox's Param<T>::Description), and that one list serves:
//  - reading YAML strictly (YamlIn, params_yaml_in.h: absent keys keep their values, unknown
//    keys and bad values are errors naming the file, the key path and the value),
//  - writing YAML (YamlOut: every key, in the order visited, floats as the doubles they are)
//    and JSON (JsonOut: numbers as the C++ types they are, for result records),
//  - validating a struct built in code (validate_params),
//  - equality (same_params), the reference of every setting (describe_params) and the
//    commented settings files of configs/ (YamlDoc, params_yaml_doc).
// What a number must satisfy (Limits) and a value's text are in params_limits.h; this header
// includes it and params_yaml_in.h, so one include gives every archive.
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

#include <cstdint>
#include <initializer_list>
#include <map>
#include <string>
#include <type_traits>
#include <vector>

#include "canopy/common/enum_names.h"
#include "canopy/common/error.h"
#include "canopy/common/params_limits.h"
#include "canopy/common/params_yaml_in.h"
#include "canopy/common/yaml_reader.h"

namespace canopy {

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
