#include "canopy/settings/settings.h"

#include <filesystem>
#include <sstream>

#include "canopy/common/error.h"

namespace canopy::settings {

std::vector<std::string> exploration_planner_names() {
  std::vector<std::string> names = {"none"};
  for (const nbv::ViewPlannerEntry& e : nbv::view_planner_registry())
    if (!e.reads_ground_truth) names.push_back(e.name);
  return names;
}

namespace {

Settings read_bundle(YamlReader& y, const std::string& dir, const RobotConfig& robot) {
  Settings s = Settings::defaults(robot);
  YamlIn in(y, /*section_files=*/true, dir);
  s.visit(in);
  y.finish();
  return s;
}

std::vector<std::string> split_key(const std::string& key) {
  std::vector<std::string> parts;
  std::stringstream ss(key);
  std::string part;
  while (std::getline(ss, part, '.')) parts.push_back(part);
  return parts;
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

YAML::Node Settings::to_yaml() const { return params_to_yaml(*this); }

std::string Settings::to_yaml_text() const { return yaml_text(to_yaml()); }

void Settings::set(const std::string& key, const std::string& value, const std::string& where) {
  std::vector<std::string> parts = split_key(key);
  if (parts.empty() || key.back() == '.')  // "", ".", "mission.loop."
    throw InputError(where + ": the setting's key path '" + key + "' is empty or ends with '.' (settings are named "
                     "by key paths such as mission.loop.views_per_stop)");
  // A planner section's former name (nbv.planner, now nbv.ours) is still read, as in a file.
  if (parts.size() >= 2 && parts[0] == "nbv")
    for (const nbv::PlannerSection& section : nbv.planners)
      if (!section.former_key.empty() && parts[1] == section.former_key) {
        warn_renamed_key(where, "nbv." + section.former_key, "nbv." + section.key);
        parts[1] = section.key;
      }
  YAML::Node root = to_yaml();
  YAML::Node node = root;
  for (std::size_t i = 0; i < parts.size(); ++i) {
    const YAML::Node& parent = node;
    if (parts[i].empty() || !parent.IsMap() || !parent[parts[i]])
      throw InputError(where + ": unknown setting '" + key + "' (settings are named by key paths such as "
                       "mission.loop.views_per_stop)");
    if (i + 1 < parts.size()) node.reset(node[parts[i]]);
  }
  YAML::Node parsed;
  try {
    parsed = YAML::Load(value);
  } catch (const YAML::Exception& e) {
    throw InputError(where + ": setting '" + key + "': value '" + value + "' is not valid YAML (" + e.msg + ")");
  }
  node[parts.back()] = parsed;
  YamlReader y(root, where, "");
  Settings s = *this;
  YamlIn in(y);
  s.visit(in);
  y.finish();
  *this = s;
}

void Settings::apply(const std::vector<SettingOverride>& overrides, const std::string& where) {
  for (const auto& [key, value] : overrides) set(key, value, where);
}

std::vector<ParamDescription> Settings::describe() const { return describe_params(*this); }

SettingOverride parse_override(const std::string& text, const std::string& where) {
  const std::size_t eq = text.find('=');
  if (eq == std::string::npos || eq == 0 || eq + 1 == text.size())
    throw InputError(where + ": '" + text + "' is not KEY=VALUE (e.g. mission.loop.views_per_stop=6)");
  return {text.substr(0, eq), text.substr(eq + 1)};
}

std::vector<SettingOverride> parse_overrides(const std::vector<std::string>& texts, const std::string& where) {
  std::vector<SettingOverride> out;
  for (const std::string& text : texts) {
    SettingOverride kv = parse_override(text, where);
    for (const SettingOverride& earlier : out)
      if (earlier.first == kv.first)
        throw InputError(where + ": key '" + kv.first + "' is given twice ('" + earlier.first + "=" + earlier.second +
                         "' and '" + text + "'); give it once");
    out.push_back(std::move(kv));
  }
  return out;
}

std::string default_settings_path() { return "configs/canopy.yaml"; }

nbv::ViewPlannerSettings planner_settings(const Settings& s, const CameraIntrinsics& intrinsics) {
  nbv::ViewPlannerSettings ps;
  ps.params = s.nbv;
  ps.intrinsics = intrinsics;
  ps.method = s.method;
  return ps;
}

std::vector<std::string> generated_settings_files() { return {"canopy", "nbv"}; }

std::string settings_file_text(const std::string& name, const std::string& where) {
  const std::string written_by =
      "# Written by `canopy settings --file " + name + "` from the parameter structs' visit(); a test holds this\n"
      "# file to it: change the structs (their defaults and help), then write it again.\n";
  if (name == "canopy") {
    YamlDoc method;
    nbv::MethodChoice choice;
    method.section("method", choice, "Which planner picks the views (canopy mission --method, --gain, --rays)");
    return "# canopy's settings bundle: what every command's --config reads. Each section is either the\n"
           "# component's keys inline or a component file relative to this one; a missing section keeps\n"
           "# the defaults (which equal the files below). A run saves its bundle, every section inline, as\n"
           "# settings.yaml; `--config that/settings.yaml` repeats the run.\n" +
           written_by + method.text +
           "mapping: mapping.yaml\n"
           "nbv: nbv.yaml\n"
           "motion: motion.yaml\n"
           "mission: mission.yaml\n";
  }
  if (name == "nbv")
    return params_yaml_doc(nbv::NbvParams{},
                           "# Next-best-view settings (the bundle's nbv section): clustering, candidates, rays, gains,\n"
                           "# the rules of taken views, then each view planner's own section (from its room,\n"
                           "# nbv/planners/<name>/<name>_params.h, through its registry entry). Values are the paper's\n"
                           "# (Table I) and docs/background/nbv_pipeline.md's.\n" +
                               written_by);
  throw InputError(where + ": '" + name + "' is not a generated settings file (known: " +
                   params_detail::join(generated_settings_files()) + ")");
}

}  // namespace canopy::settings
