#include "cli_util.h"

#include "canopy/common/data_dir.h"

namespace canopy::cli {

std::string default_world_path() { return "worlds/default.yaml"; }

settings::Settings load_settings(const std::string& path) {
  return settings::Settings::load(find_data_file(path), default_robot_config());
}

}  // namespace canopy::cli
