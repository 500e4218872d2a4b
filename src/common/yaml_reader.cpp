#include "canopy/common/yaml_reader.h"

#include <map>

#include "canopy/common/io.h"

namespace canopy {

YamlReader::YamlReader(YAML::Node node, std::string file, std::string path)
    : node_(std::move(node)), file_(std::move(file)), path_(std::move(path)) {
  if (node_ && !node_.IsNull() && !node_.IsMap()) {
    throw InputError(file_ + (path_.empty() ? std::string(": the document") : ": key '" + path_ + "'") +
                     " must be a mapping of keys to values");
  }
}

YamlReader YamlReader::load_file(const std::string& file) { return load_string(read_file(file), file); }

namespace {
// yaml-cpp keeps every pair of a mapping with a repeated key but looks up only the first:
// a repeated key would silently lose its later value. Rejects them anywhere in the tree.
void reject_duplicate_keys(const YAML::Node& node, const std::string& name) {
  if (node.IsMap()) {
    std::map<std::string, int> line_of;  // key -> 1-based line
    for (const auto& kv : node) {
      const int line = kv.first.Mark().line + 1;
      const std::string key = kv.first.IsScalar() ? kv.first.Scalar() : std::string("<complex key>");
      const auto [it, inserted] = line_of.emplace(key, line);
      if (!inserted)
        throw InputError(name + ": duplicate key '" + key + "' at lines " + std::to_string(it->second) + " and " +
                         std::to_string(line));
      reject_duplicate_keys(kv.second, name);
    }
  } else if (node.IsSequence()) {
    for (const auto& item : node) reject_duplicate_keys(item, name);
  }
}
}  // namespace

YamlReader YamlReader::load_string(const std::string& text, const std::string& name) {
  YAML::Node root;
  try {
    root = YAML::Load(text);
  } catch (const YAML::Exception& e) {
    throw InputError(name + ": malformed YAML at line " + std::to_string(e.mark.line + 1) + ": " + e.msg);
  }
  reject_duplicate_keys(root, name);
  return YamlReader(root, name, "");
}

bool YamlReader::has(const std::string& key) const {
  return node_ && node_.IsMap() && node_[key] && !node_[key].IsNull();
}

std::string YamlReader::key_path(const std::string& key) const {
  return path_.empty() ? key : path_ + "." + key;
}

std::string YamlReader::value_text(const std::string& key) const {
  if (!has(key)) return "";
  const YAML::Node v = node_[key];
  if (v.IsScalar()) return v.Scalar();
  YAML::Emitter e;
  e << YAML::Flow << v;
  return e.c_str();
}

bool YamlReader::value_is_scalar(const std::string& key) const { return has(key) && node_[key].IsScalar(); }

void YamlReader::fail(const std::string& key, const std::string& problem) const {
  throw InputError(file_ + ": key '" + key_path(key) + "': value '" + value_text(key) + "' " + problem);
}

YamlReader YamlReader::child(const std::string& key) {
  read_.insert(key);
  if (!has(key)) return YamlReader(YAML::Node(YAML::NodeType::Map), file_, key_path(key));
  return YamlReader(node_[key], file_, key_path(key));
}

void YamlReader::finish() const {
  if (!node_ || !node_.IsMap()) return;
  for (const auto& kv : node_) {
    const std::string key = kv.first.as<std::string>();
    if (!read_.count(key)) throw InputError(file_ + ": unknown key '" + key_path(key) + "'");
  }
}

}  // namespace canopy
