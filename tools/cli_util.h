#pragma once
// Helpers shared by the command implementations.

#include <nlohmann/json.hpp>

#include <string>

#include "canopy/robot/robot_config.h"
#include "canopy/mission/settings.h"
#include "canopy/world/world.h"
#include "canopy/world/world_spec.h"

namespace canopy::cli {

/// Default world file, relative to the data folder (shown so in --help).
std::string default_world_path();
/// Loads a world file (a relative path missing from the current folder is looked up in the
/// data folder, see data_dir.h), checks that the robot's base fits its aisle (robot.yaml
/// aisle_clearance_m) and logs what it is. Throws InputError on problems.
world::WorldSpec load_world_spec(const std::string& path, const RobotConfig& robot = default_robot_config());
/// Generates the world of `spec` and logs a warning for each plant whose drawn fruits did not
/// all fit (world::unplaced_fruit_notes).
world::World build_world(const world::WorldSpec& spec);
/// Checks the colours of every imported plant of `world` against the colour segmentation of
/// `extractor` (evaluation/segmentation_check.h) and logs what it gives per material. Under
/// colour segmentation a target-fruit material it would not label fruit is an InputError
/// naming the plant and the material; other problems (a leaf material labelled fruit, or any
/// problem under --seg truth) are warnings.
void check_world_colours(const world::World& world, const perception::ExtractorParams& extractor);
/// The start of a command's run.yaml: the command, the world file and the world's resolved
/// parameters (seed included). Commands add their own options; the settings bundle goes to
/// settings.yaml beside it.
YAML::Node run_record(const std::string& command, const world::WorldSpec& spec);
/// Loads the settings bundle every command's --config names, found like a world file
/// (InputError on problems).
mission::Settings load_settings(const std::string& path);
/// Help text of --config.
constexpr const char* kConfigHelp = "Settings bundle (YAML: mapping, nbv, motion, mission sections)";

}  // namespace canopy::cli
