#include "canopy/common/params.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <cstdlib>
#include <filesystem>

#include "canopy/common/value_text.h"
#include "canopy/common/warning.h"

namespace canopy {

namespace {
std::string number(double v) {
  YAML::Emitter e;
  e.SetDoublePrecision(15);
  e << v;
  return e.c_str();
}
}  // namespace

std::string Limits::text() const {
  const bool has_lo = std::isfinite(lo), has_hi = std::isfinite(hi);
  if (!has_lo && !has_hi) return "must be a finite number";
  if (has_lo && !has_hi) return std::string("must be ") + (lo_open ? "> " : ">= ") + number(lo);
  if (!has_lo) return std::string("must be ") + (hi_open ? "< " : "<= ") + number(hi);
  return std::string("must be in ") + (lo_open ? "(" : "[") + number(lo) + ", " + number(hi) + (hi_open ? ")" : "]");
}

namespace params_detail {
namespace {
// %g switches to an exponent once a number has more integer digits than the precision ("3e+01"
// for 30 at one digit); below 1e15 more digits print it in plain decimals and still read back.
std::string plain_decimals(char* b, std::size_t size, int p, double v) {
  while (std::strchr(b, 'e') && std::fabs(v) >= 1.0 && std::fabs(v) < 1e15 && p < 17)
    c_snprintf(b, size, "%.*g", ++p, v);
  return b;
}
}  // namespace

std::string shortest(double v) {
  char b[40];
  int p = 1;
  for (; p <= 17; ++p) {
    c_snprintf(b, sizeof b, "%.*g", p, v);
    if (c_strtod(b, nullptr) == v) break;
  }
  return plain_decimals(b, sizeof b, std::min(p, 17), v);
}

std::string shortest(float v) {
  char b[40];
  int p = 1;
  for (; p <= 9; ++p) {
    c_snprintf(b, sizeof b, "%.*g", p, double(v));
    if (static_cast<float>(c_strtod(b, nullptr)) == v) break;
  }
  return plain_decimals(b, sizeof b, std::min(p, 9), double(v));
}

std::string tuple_text(const char* shape, bool whole, const Limits& each) {
  std::string lim = each.text();
  if (lim.rfind("must be ", 0) == 0) lim = lim.substr(8);
  return std::string(shape) + (whole ? " of whole numbers, each " : " of numbers, each ") + lim;
}

std::string join(const std::vector<std::string>& names) {
  std::string s;
  for (const auto& n : names) s += (s.empty() ? "" : ", ") + n;
  return s;
}
}  // namespace params_detail

std::string YamlIn::resolve(const std::string& path) const {
  std::filesystem::path p(path);
  if (p.is_relative() && !dir_.empty()) p = std::filesystem::path(dir_) / p;
  return p.string();
}

void YamlIn::renamed(const char* old_key, const char* key) {
  if (!y_.has(old_key)) return;
  if (y_.has(key))
    throw InputError(y_.file() + ": keys '" + y_.key_path(old_key) + "' and '" + y_.key_path(key) +
                     "' name the same settings (the former name and the current one); give '" + key + "' only");
  warn_renamed_key(y_.file(), y_.key_path(old_key), y_.key_path(key));
  y_.rename(old_key, key);
}

void warn_renamed_key(const std::string& where, const std::string& old_path, const std::string& new_path) {
  warn(where + ": key '" + old_path + "' is now '" + new_path + "'; read as such (rename it: the old name will be refused)");
}

std::string YamlDoc::flow(const YAML::Node& node) {
  YAML::Emitter e;
  e << YAML::Flow << node;
  return e.c_str();
}

void YamlDoc::line(const char* key, const std::string& value, const std::string& help) {
  std::string l = std::string(static_cast<std::size_t>(indent_), ' ') + key + ":" + (value.empty() ? "" : " " + value);
  if (!help.empty()) l += std::string(l.size() < 30 ? 30 - l.size() : 2, ' ') + "# " + help;
  text += l + "\n";
}

nlohmann::json yaml_to_json(const YAML::Node& node) {
  if (node.IsMap()) {
    nlohmann::json j = nlohmann::json::object();
    for (const auto& kv : node) j[kv.first.as<std::string>()] = yaml_to_json(kv.second);
    return j;
  }
  if (node.IsSequence()) {
    nlohmann::json j = nlohmann::json::array();
    for (const auto& v : node) j.push_back(yaml_to_json(v));
    return j;
  }
  if (!node.IsScalar()) return nullptr;
  const std::string s = node.Scalar();
  if (s == "true") return true;
  if (s == "false") return false;
  try {
    std::size_t used = 0;
    const long long i = std::stoll(s, &used);
    if (used == s.size()) return i;
  } catch (const std::exception&) {
  }
  try {
    std::size_t used = 0;
    const double d = c_stod(s, &used);
    if (used == s.size()) return d;
  } catch (const std::exception&) {
  }
  return s;
}

std::string params_markdown(const std::vector<ParamDescription>& rows) {
  std::string out = "| key | default | must be | meaning |\n| --- | --- | --- | --- |\n";
  for (const ParamDescription& p : rows) {
    std::string value = p.value;  // a '|' would end the cell
    for (std::size_t i = 0; (i = value.find('|', i)) != std::string::npos; i += 2) value.replace(i, 1, "\\|");
    out += "| `" + p.key + "` | `" + value + "` | " + p.limits + " | " + p.help + " |\n";
  }
  return out;
}

std::string yaml_text(const YAML::Node& node) {
  YAML::Emitter e;
  e.SetDoublePrecision(17);
  e << node;
  return std::string(e.c_str()) + "\n";
}

}  // namespace canopy
