#include "cli_util.h"

#include "canopy/common/data_dir.h"

namespace canopy::cli {

std::string default_world_path() { return "worlds/default.yaml"; }

mission::Settings load_settings(const std::string& path) {
  return mission::Settings::load(find_data_file(path), default_robot_config());
}

}  // namespace canopy::cli
