// canopy: active semantic mapping with a mobile manipulator, headless in MuJoCo.

#include <spdlog/sinks/stdout_color_sinks.h>
#include <spdlog/spdlog.h>

#include <cstdio>
#include <exception>

#include "canopy/common/error.h"
#include "commands.h"

int main(int argc, char** argv) {
  CLI::App app{"canopy: simulator and planner for active semantic mapping in greenhouses"};
  app.require_subcommand(1);
  app.set_help_all_flag("--help-all", "Show help for every subcommand");
  spdlog::set_pattern("[%H:%M:%S.%e] %^%l%$ %v");
  spdlog::set_default_logger(spdlog::stderr_color_mt("canopy"));

  canopy::cli::add_world_command(app);
  canopy::cli::add_render_command(app);
  canopy::cli::add_run_command(app);
  canopy::cli::add_mission_command(app);
  canopy::cli::add_map_command(app);
  canopy::cli::add_ablate_command(app);
  canopy::cli::add_reach_command(app);
  CLI::App* bench = app.add_subcommand("bench", "Benchmarks that print timings (not tests)");
  bench->require_subcommand(1);
  canopy::cli::add_bench_render(*bench);
  canopy::cli::add_bench_map(*bench);
  canopy::cli::add_bench_gain(*bench);
  canopy::cli::add_bench_motion(*bench);

  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    const int code = app.exit(e);
    return code == 0 ? 0 : 2;
  } catch (const canopy::Interrupted& e) {
    std::fprintf(stderr, "canopy: %s\n", e.what());
    return 130;
  } catch (const canopy::InputError& e) {
    std::fprintf(stderr, "canopy: error: %s\n", e.what());
    return 2;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "canopy: internal error: %s\n", e.what());
    return 1;
  }
  return 0;
}
