#pragma once
// One settings bundle per run: mapping, next-best-view, motion and mission settings, loaded,
// validated and saved the same way by every command. `--config FILE` always names a bundle:
// a YAML mapping with the optional sections `mapping`, `nbv`, `motion`, `mission`; each is
// either the section's keys inline or the path of a component file (relative to the bundle),
// and an absent section keeps its defaults. configs/canopy.yaml names the four files in
// configs/. A run saves its bundle inline as settings.yaml, which loads back to the same
// settings (`--config results/settings.yaml` repeats a run).

#include <string>

#include <yaml-cpp/yaml.h>

#include "canopy/robot/robot_config.h"
#include "canopy/evaluation/map_metrics.h"
#include "canopy/mapping/mapping_config.h"
#include "canopy/mission/mission_params.h"
#include "canopy/motion/motion_config.h"
#include "canopy/nbv/nbv_params.h"

namespace canopy::mission {

struct Settings {
  mapping::MappingConfig mapping;
  evaluation::MetricsParams metrics;  ///< Saved in the mapping section, key `metrics`.
  nbv::NbvParams nbv;
  motion::MotionConfig motion;
  MissionParams mission;

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
};

/// The default bundle, relative to the data folder: "configs/canopy.yaml" (find_data_file
/// resolves it).
std::string default_settings_path();

}  // namespace canopy::mission
