#pragma once
// One settings bundle per run: the method and the mapping, next-best-view, motion and mission
// settings, loaded, validated and saved the same way by every command. `--config FILE` always
// names a bundle: a YAML mapping with the optional sections `method`, `mapping`, `nbv`,
// `motion`, `mission`; each is either the section's keys inline or the path of a component
// file (relative to the bundle), and an absent section keeps its defaults. configs/canopy.yaml
// names the files in configs/. A run saves its bundle inline as settings.yaml, which loads
// back to the same settings (`--config results/settings.yaml` repeats a run).
//
// Every key is stated once, in its struct's visit() (common/params.h); a setting is named by
// its key path ("mission.loop.views_per_stop"), which is how experiments and the ablation
// sweep any of them (Settings::set).

#include <string>
#include <utility>
#include <vector>

#include <yaml-cpp/yaml.h>

#include "canopy/common/params.h"
#include "canopy/evaluation/map_metrics.h"
#include "canopy/mapping/map_params.h"
#include "canopy/settings/mission_params.h"
#include "canopy/motion/motion_config.h"
#include "canopy/nbv/nbv_params.h"
#include "canopy/nbv/view_planner.h"
#include "canopy/perception/semantic_extractor.h"
#include "canopy/robot/robot_config.h"

namespace canopy::settings {

/// The bundle's `mapping` section: the map, the extractor and the evaluation of the map.
struct MappingSettings {
  mapping::SemanticMapParams map;
  perception::ExtractorParams extractor;
  evaluation::MetricsParams metrics;

  template <class A>
  void visit(A& a) {
    a.section("map", map, "The semantic octree and insertion");
    a.section("extractor", extractor, "Segmentation, noise and point clouds");
    a.section("metrics", metrics, "Evaluation against the ground truth");
  }
};

/// A setting named by its key path and a YAML value ("mission.loop.views_per_stop", "6").
using SettingOverride = std::pair<std::string, std::string>;

struct Settings {
  nbv::MethodChoice method;
  MappingSettings mapping;
  nbv::NbvParams nbv;
  motion::MotionConfig motion;
  MissionParams mission;

  template <class A>
  void visit(A& a) {
    a.section("method", method, "Which planner picks the views");
    a.section("mapping", mapping, "Mapping and evaluation");
    a.section("nbv", nbv, "Next-best-view planning");
    a.section("motion", motion, "Arm and base motion");
    a.section("mission", mission, "The closed-loop mission");
  }

  /// Struct defaults (which equal configs/*.yaml).
  static Settings defaults(const RobotConfig& robot);
  /// Loads a bundle; throws InputError naming the file and key on any problem (unknown
  /// sections and keys too).
  static Settings load(const std::string& path, const RobotConfig& robot);
  /// Parses bundle text; `name` stands in for the file, relative paths are read from `dir`.
  static Settings load_string(const std::string& text, const std::string& name, const std::string& dir,
                              const RobotConfig& robot);
  /// Every section inline.
  YAML::Node to_yaml() const;
  std::string to_yaml_text() const;
  /// Sets the setting at `key` (a key path such as "nbv.gain.proximity") to `value` (YAML
  /// text) and validates the result; throws InputError naming `where` for an unknown key or a
  /// bad value.
  void set(const std::string& key, const std::string& value, const std::string& where);
  /// set() for each override in order.
  void apply(const std::vector<SettingOverride>& overrides, const std::string& where);
  /// Every setting with its default, limits and help.
  std::vector<ParamDescription> describe() const;
  bool operator==(const Settings& o) const { return to_yaml_text() == o.to_yaml_text(); }
};

/// What a planner is built from, out of a bundle: its method, the nbv section and the camera; the
/// context is left for a mission to set.
nbv::ViewPlannerSettings planner_settings(const Settings& s, const CameraIntrinsics& intrinsics);
/// Parses "key=value" (the value is YAML); throws InputError naming `where`.
SettingOverride parse_override(const std::string& text, const std::string& where);
/// parse_override of each text; a key given twice is an InputError naming both (a repeated
/// `--set` would otherwise keep the last silently).
std::vector<SettingOverride> parse_overrides(const std::vector<std::string>& texts, const std::string& where);

/// The default bundle, relative to the data folder: "configs/canopy.yaml" (find_data_file
/// resolves it).
std::string default_settings_path();

/// The shipped settings files written from the struct defaults (YamlDoc: each key with its
/// help): "canopy" (configs/canopy.yaml: the method inline, the other sections by file) and
/// "nbv" (configs/nbv.yaml). A test holds configs/ to them; `canopy settings --file NAME`
/// prints them.
std::vector<std::string> generated_settings_files();
/// The text of one of them; throws InputError naming `where` for another name.
std::string settings_file_text(const std::string& name, const std::string& where);

}  // namespace canopy::settings
