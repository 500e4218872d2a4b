#include "canopy/mission/settings.h"

#include <filesystem>

#include "canopy/common/error.h"

namespace canopy::mission {

namespace {

// MotionConfig reports itself as JSON; the bundle is YAML (JSON's types map one to one).
YAML::Node json_to_yaml(const nlohmann::json& j) {
  YAML::Node n;
  if (j.is_object()) {
    for (auto it = j.begin(); it != j.end(); ++it) n[it.key()] = json_to_yaml(it.value());
  } else if (j.is_array()) {
    n = YAML::Node(YAML::NodeType::Sequence);
    for (const auto& v : j) n.push_back(json_to_yaml(v));
  } else if (j.is_boolean()) {
    n = j.get<bool>();
  } else if (j.is_number_unsigned()) {
    n = j.get<std::uint64_t>();
  } else if (j.is_number_integer()) {
    n = j.get<std::int64_t>();
  } else if (j.is_number_float()) {
    n = j.get<double>();
  } else if (j.is_string()) {
    n = j.get<std::string>();
  }
  return n;
}

Settings read_bundle(YamlReader& y, const std::string& dir, const RobotConfig& robot) {
  Settings s = Settings::defaults(robot);
  auto component = [&](const std::string& key, auto&& read) {
    if (!y.has(key)) return;
    std::string path;
    bool is_path = false;
    try {
      path = y.require<std::string>(key);
      is_path = true;
    } catch (const InputError&) {
    }
    if (is_path) {
      std::filesystem::path p(path);
      if (p.is_relative()) p = std::filesystem::path(dir) / p;
      YamlReader c = YamlReader::load_file(p.string());
      read(c);
      c.finish();
    } else {
      YamlReader c = y.child(key);
      read(c);
      c.finish();
    }
  };
  component("mapping", [&](YamlReader& c) {
    s.mapping = mapping::MappingConfig::from_yaml(c);
    YamlReader me = c.child("metrics");
    s.metrics = evaluation::MetricsParams::from_yaml(me);
    me.finish();
  });
  component("nbv", [&](YamlReader& c) { s.nbv = nbv::NbvParams::from_yaml(c); });
  component("motion", [&](YamlReader& c) { s.motion = motion::MotionConfig::from_yaml(c, robot); });
  component("mission", [&](YamlReader& c) { s.mission = MissionParams::from_yaml(c); });
  y.finish();
  return s;
}

}  // namespace

Settings Settings::defaults(const RobotConfig& robot) {
  Settings s;
  s.motion = motion::MotionConfig::defaults(robot);
  return s;
}

Settings Settings::load(const std::string& path, const RobotConfig& robot) {
  std::error_code ec;
  if (std::filesystem::is_directory(path, ec))
    throw InputError(path + ": is a folder, not a settings file (--config names a YAML bundle)");
  YamlReader y = YamlReader::load_file(path);
  return read_bundle(y, std::filesystem::path(path).parent_path().string(), robot);
}

Settings Settings::load_string(const std::string& text, const std::string& name, const std::string& dir,
                               const RobotConfig& robot) {
  YamlReader y = YamlReader::load_string(text, name);
  return read_bundle(y, dir, robot);
}

YAML::Node Settings::to_yaml() const {
  YAML::Node n;
  n["mapping"] = mapping.to_yaml();
  n["mapping"]["metrics"] = metrics.to_yaml();
  n["nbv"] = nbv.to_yaml();
  n["motion"] = json_to_yaml(motion.to_json());
  n["mission"] = mission.to_yaml();
  return n;
}

std::string Settings::to_yaml_text() const {
  YAML::Emitter e;
  e.SetDoublePrecision(17);
  e << to_yaml();
  return std::string(e.c_str()) + "\n";
}

std::string default_settings_path() { return "configs/canopy.yaml"; }

}  // namespace canopy::mission
