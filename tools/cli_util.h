#pragma once
// Helpers shared by the command implementations. Loading and checking a world is a job of
// the library (canopy/jobs/world_job.h), shared with Python.

#include <nlohmann/json.hpp>

#include <string>
#include <vector>

#include "canopy/jobs/world_job.h"
#include "canopy/settings/settings.h"
#include "canopy/robot/robot_config.h"

namespace canopy::cli {

/// Default world file, relative to the data folder (shown so in --help).
std::string default_world_path();
/// Loads the settings bundle every command's --config names, found like a world file
/// (InputError on problems).
settings::Settings load_settings(const std::string& path);
/// Sets each --set KEY=VALUE on `bundle`, in order (InputError naming the one that fails).
void apply_set_options(settings::Settings& bundle, const std::vector<std::string>& texts);
/// Help text of --config.
constexpr const char* kStrictColoursHelp =
    "Refuse the world when colour segmentation would label a non-fruit material (floor, leaf) fruit "
    "(default: a warning)";
constexpr const char* kConfigHelp = "Settings bundle (YAML: mapping, nbv, motion, mission sections)";

}  // namespace canopy::cli
