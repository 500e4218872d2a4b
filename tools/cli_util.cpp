#include "cli_util.h"

#include "canopy/common/data_dir.h"

namespace canopy::cli {

std::string default_world_path() { return "worlds/default.yaml"; }

settings::Settings load_settings(const std::string& path) {
  return settings::Settings::load(find_data_file(path), default_robot_config());
}

void apply_set_options(settings::Settings& bundle, const std::vector<std::string>& texts) {
  for (const settings::SettingOverride& kv : settings::parse_overrides(texts, "--set"))
    bundle.set(kv.first, kv.second, "--set " + kv.first);
}

}  // namespace canopy::cli
