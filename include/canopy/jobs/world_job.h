#pragma once
// Job: load and check a world. What every command that builds a world and Python's
// canopy.World do, in one place: the world file read (looked up in the data folder), the
// robot's base checked against the aisle, the world generated, and the colours of every
// material (ground, plants, robot) checked against the colour segmentation of the labels it
// will be mapped with.

#include <yaml-cpp/yaml.h>

#include <cstdint>
#include <optional>
#include <string>

#include "canopy/perception/semantic_extractor.h"
#include "canopy/robot/robot_config.h"
#include "canopy/robot/robot_description.h"
#include "canopy/world/world.h"
#include "canopy/world/world_spec.h"

namespace canopy::jobs {

/// What load_world needs.
struct WorldJobParams {
  std::string world_file;                    ///< As given; a relative path missing here is looked up in the data folder.
  std::optional<std::uint64_t> seed;         ///< Replaces the file's seed when given.
  perception::ExtractorParams extractor;     ///< The labels the world will be mapped with (the colour check).
  RobotConfig robot = default_robot_config();  ///< Whose base must fit the aisle.
  bool strict_colours = false;               ///< A non-fruit material coloured like fruit is an error, not a warning.
};

/// The base's reach from the robot's URDF: its planar joints' ranges and the arm's offset on it.
world::WorldSpec::BaseRange base_range(const RobotConfig& robot, const robot::RobotDescription& description);

/// Reads a world file (found like data files, data_dir.h), replaces its seed when `seed` is
/// given, checks that the robot's base fits its aisle (robot.yaml aisle_clearance_m) and can
/// stand beside every plant of the rows and at robot_start within its joints' ranges, and logs
/// what it is. Throws InputError on problems.
world::WorldSpec load_world_spec(const std::string& path, const RobotConfig& robot = default_robot_config(),
                                 std::optional<std::uint64_t> seed = std::nullopt);

/// Generates the world of `spec` and logs a warning for each plant whose drawn fruits did not
/// all fit (world::unplaced_fruit_notes). A world of sim::SceneOptions::plant_window_min_triangles
/// triangles or more keeps its plants' parts only while they are used (world::GenerateOptions,
/// World::plant()); smaller ones hold every plant.
world::World build_world(const world::WorldSpec& spec);

/// Checks the colours of every material of `world` and of the robot's visual shapes against the
/// colour segmentation of `extractor` (evaluation/segmentation_check.h), logs the imported
/// plants' materials and a summary line. Under colour segmentation a target-fruit material it
/// would not label fruit is an InputError naming the owner and the material. A non-fruit
/// material it would label fruit (a fruit-coloured floor, a leaf material) is a warning, an
/// InputError when `strict` under colour labels; on the robot it is harmless (the wrist camera's self-filter drops
/// the robot's own pixels) and only logged at debug level.
void check_world_colours(const world::World& world, const perception::ExtractorParams& extractor,
                         bool strict = false, const RobotConfig& robot = default_robot_config());

/// The whole job: load_world_spec, build_world and check_world_colours.
world::World load_world(const WorldJobParams& params);

/// The start of a command's run.yaml: the command, the world file and the world's resolved
/// parameters (seed included). Commands add their own options.
YAML::Node run_record(const std::string& command, const world::WorldSpec& spec);

}  // namespace canopy::jobs
