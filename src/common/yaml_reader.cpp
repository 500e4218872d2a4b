#include "canopy/common/yaml_reader.h"

#include <map>
#include <sstream>

#include <yaml-cpp/eventhandler.h>
#include <yaml-cpp/parser.h>

#include "canopy/common/read_file.h"

namespace canopy {

YamlReader::YamlReader(YAML::Node node, std::string file, std::string path)
    : node_(std::move(node)), file_(std::move(file)), path_(std::move(path)) {
  if (node_ && !node_.IsNull() && !node_.IsMap()) {
    throw InputError(file_ + (path_.empty() ? std::string(": the document") : ": key '" + path_ + "'") +
                     " must be a mapping of keys to values");
  }
}

YamlReader YamlReader::load_file(const std::string& file) {
  const std::string text = read_file(file, kMaxYamlFileBytes);
  if (text.find_first_not_of(" \t\r\n") == std::string::npos)
    throw InputError(file + ": is empty (write {} to take every default)");
  return load_string(text, file);
}

namespace {

// Counts the nodes of the first document with every alias expanded, from the parser's
// events (linear in the text), and stops as soon as the count passes kMaxYamlNodes.
class ExpandedSize : public YAML::EventHandler {
 public:
  explicit ExpandedSize(std::string name) : name_(std::move(name)) {}
  void OnDocumentStart(const YAML::Mark&) override {}
  void OnDocumentEnd() override {}
  void OnNull(const YAML::Mark&, YAML::anchor_t anchor) override { leaf(anchor); }
  void OnAlias(const YAML::Mark&, YAML::anchor_t anchor) override {
    const auto it = anchored_.find(anchor);
    add(it == anchored_.end() ? 1 : it->second);
  }
  void OnScalar(const YAML::Mark&, const std::string&, YAML::anchor_t anchor, const std::string&) override {
    leaf(anchor);
  }
  void OnSequenceStart(const YAML::Mark&, const std::string&, YAML::anchor_t anchor, YAML::EmitterStyle::value) override {
    open_.push_back({anchor, 1});
  }
  void OnSequenceEnd() override { close(); }
  void OnMapStart(const YAML::Mark&, const std::string&, YAML::anchor_t anchor, YAML::EmitterStyle::value) override {
    open_.push_back({anchor, 1});
  }
  void OnMapEnd() override { close(); }

 private:
  void leaf(YAML::anchor_t anchor) {
    if (anchor != YAML::NullAnchor) anchored_[anchor] = 1;
    add(1);
  }
  void close() {
    const auto [anchor, size] = open_.back();
    open_.pop_back();
    if (anchor != YAML::NullAnchor) anchored_[anchor] = size;
    add(size);
  }
  void add(std::uint64_t n) {
    std::uint64_t& into = open_.empty() ? total_ : open_.back().second;
    into += n;
    if (into > kMaxYamlNodes || n > kMaxYamlNodes)
      throw InputError(name_ + ": the YAML document expands to more than " + std::to_string(kMaxYamlNodes) +
                       " nodes (nested aliases?); write the values out");
  }
  std::string name_;
  std::vector<std::pair<YAML::anchor_t, std::uint64_t>> open_;
  std::map<YAML::anchor_t, std::uint64_t> anchored_;
  std::uint64_t total_ = 0;
};

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
    std::istringstream in(text);
    YAML::Parser parser(in);
    ExpandedSize size(name);
    parser.HandleNextDocument(size);
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

namespace {
void set_flow(YAML::Node n) {
  if (n.IsMap() || n.IsSequence()) n.SetStyle(YAML::EmitterStyle::Flow);
  if (n.IsSequence())
    for (YAML::Node c : n) set_flow(c);
  if (n.IsMap())
    for (auto kv : n) set_flow(kv.second);
}
}  // namespace

std::string YamlReader::value_text(const std::string& key) const {
  if (!has(key)) return "";
  const YAML::Node v = node_[key];
  std::string text;
  if (v.IsScalar()) {
    text = v.Scalar();
  } else {
    // Block lists and mappings in flow style: an error message stays on one line.
    YAML::Node flow = YAML::Clone(v);
    set_flow(flow);
    YAML::Emitter e;
    e << YAML::Flow << flow;
    text = e.c_str();
  }
  for (char& c : text)
    if (c == '\n' || c == '\r') c = ' ';
  // A value of megabytes is named by its start.
  if (text.size() > 200) text = text.substr(0, 200) + "...";
  return text;
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

bool YamlReader::rename(const std::string& old_key, const std::string& new_key) {
  if (!has(old_key)) return false;
  const YAML::Node value = node_[old_key];
  node_.remove(old_key);
  node_[new_key] = value;
  return true;
}

void YamlReader::finish() const {
  if (!node_ || !node_.IsMap()) return;
  for (const auto& kv : node_) {
    const std::string key = kv.first.as<std::string>();
    if (!read_.count(key)) throw InputError(file_ + ": unknown key '" + key_path(key) + "'");
  }
}

}  // namespace canopy
