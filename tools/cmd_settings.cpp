// canopy settings: every setting of a bundle with its value, what it must be and what it is
// for, from the one visit() of each parameter struct (common/params.h). --markdown prints the
// table docs/settings.md holds; --file NAME the shipped settings file configs/NAME.yaml.

#include <cstdio>

#include "canopy/world/world_spec.h"
#include "cli_util.h"
#include "commands.h"

namespace canopy::cli {

void add_settings_command(CLI::App& app) {
  struct Options {
    std::string config = settings::default_settings_path();
    bool markdown = false;
    bool world = false;
    std::string file;
  };
  auto opt = std::make_shared<Options>();
  CLI::App* sub = app.add_subcommand(
      "settings", "Every setting of a bundle: key path (what --set and experiments name), value, limits, meaning");
  sub->add_option("--config", opt->config, kConfigHelp)->capture_default_str();
  sub->add_flag("--markdown", opt->markdown, "Print a Markdown table (docs/settings.md)");
  sub->add_flag("--world", opt->world, "The keys of a world file instead (docs/plants.md)");
  sub->add_option("--file", opt->file,
                  "Print the shipped settings file NAME as the structs write it (configs/NAME.yaml: canopy, nbv)");
  sub->callback([opt] {
    if (!opt->file.empty()) {
      std::fputs(settings::settings_file_text(opt->file, "--file").c_str(), stdout);
      return;
    }
    const std::vector<ParamDescription> rows =
        opt->world ? describe_params(world::WorldSpec{}) : load_settings(opt->config).describe();
    if (opt->markdown) {
      std::fputs(params_markdown(rows).c_str(), stdout);
      return;
    }
    for (const ParamDescription& p : rows)
      std::printf("%-48s %-20s %-32s %s\n", p.key.c_str(), p.value.c_str(), p.limits.c_str(), p.help.c_str());
  });
}

}  // namespace canopy::cli
