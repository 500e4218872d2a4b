// canopy settings: every setting of a bundle with its value, what it must be and what it is
// for, from the one visit() of each parameter struct (common/params.h). --markdown prints the
// table docs/settings.md holds.

#include <cstdio>

#include "canopy/common/io.h"
#include "cli_util.h"
#include "commands.h"

namespace canopy::cli {

void add_settings_command(CLI::App& app) {
  struct Options {
    std::string config = mission::default_settings_path();
    bool markdown = false;
  };
  auto opt = std::make_shared<Options>();
  CLI::App* sub = app.add_subcommand(
      "settings", "Every setting of a bundle: key path (what --set and experiments name), value, limits, meaning");
  sub->add_option("--config", opt->config, kConfigHelp)->capture_default_str();
  sub->add_flag("--markdown", opt->markdown, "Print a Markdown table (docs/settings.md)");
  sub->callback([opt] {
    const mission::Settings settings = load_settings(opt->config);
    const std::vector<ParamDescription> rows = settings.describe();
    if (opt->markdown) {
      std::printf("| key | default | must be | meaning |\n| --- | --- | --- | --- |\n");
      for (const ParamDescription& p : rows) {
        std::string value = p.value;
        for (std::size_t i = 0; (i = value.find('|', i)) != std::string::npos; i += 2) value.replace(i, 1, "\\|");
        std::printf("| `%s` | `%s` | %s | %s |\n", p.key.c_str(), value.c_str(), p.limits.c_str(), p.help.c_str());
      }
      return;
    }
    for (const ParamDescription& p : rows)
      std::printf("%-48s %-20s %-32s %s\n", p.key.c_str(), p.value.c_str(), p.limits.c_str(), p.help.c_str());
  });
}

}  // namespace canopy::cli
