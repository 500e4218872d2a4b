#include "cli_util.h"

#include <spdlog/spdlog.h>

namespace canopy::cli {

std::string default_world_path() { return find_data_file("worlds/default.yaml"); }

world::WorldSpec load_world_spec(const std::string& path) {
  world::WorldSpec spec = world::WorldSpec::load(path);
  spdlog::info("world '{}' from {}: {} plants, seed {}", spec.name, path, spec.plant_count(), spec.seed);
  return spec;
}

mission::Settings load_settings(const std::string& path) {
  return mission::Settings::load(path, default_robot_config());
}

}  // namespace canopy::cli
