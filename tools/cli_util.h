#pragma once
// Helpers shared by the command implementations.

#include <string>

#include "canopy/common/robot_config.h"
#include "canopy/mission/settings.h"
#include "canopy/world/world_spec.h"

namespace canopy::cli {

/// Default world file, found in the current directory or the source tree.
std::string default_world_path();
/// Loads a world file (InputError on problems) and logs what it is.
world::WorldSpec load_world_spec(const std::string& path);
/// Loads the settings bundle every command's --config names (InputError on problems).
mission::Settings load_settings(const std::string& path);
/// Help text of --config.
constexpr const char* kConfigHelp = "Settings bundle (YAML: mapping, nbv, motion, mission sections)";

}  // namespace canopy::cli
