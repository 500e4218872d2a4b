// canopy: active semantic mapping with a mobile manipulator, headless in MuJoCo.

#include <spdlog/sinks/stdout_color_sinks.h>
#include <spdlog/spdlog.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <filesystem>
#include <string>
#include <thread>

#include "canopy/common/error.h"
#include "canopy/common/interrupt.h"
#include "canopy/common/atomic_file.h"
#include "canopy/common/value_text.h"
#include "canopy/common/warning.h"
#include "commands.h"

namespace {

// Every error is one line (a message quoting a multi-line value must not spill).
std::string one_line(std::string s) {
  for (char& c : s)
    if (c == '\n' || c == '\r') c = ' ';
  return s;
}

// Every --seed takes decimal digits only and fits 64 bits (CLI11 would wrap "-1" and
// overflows around).
void require_valid_seeds(CLI::App& app) {
  const CLI::Validator seed(
      [](std::string& text) -> std::string {
        try {
          canopy::parse_uint64(text, "--seed");
        } catch (const canopy::InputError& e) {
          return std::string(e.what()).substr(std::string("--seed: ").size());
        }
        return std::string();
      },
      "", "SEED");
  for (CLI::Option* o : app.get_options())
    if (o->get_name() == "--seed") o->check(seed);
  for (CLI::App* s : app.get_subcommands([](CLI::App*) { return true; })) require_valid_seeds(*s);
}

std::vector<CLI::App*> subcommands(CLI::App& app) {
  return app.get_subcommands([](CLI::App*) { return true; });
}

// CLI11 calls a mistyped command an unexpected argument; say it is an unknown command and
// list the valid ones.
void check_command_names(CLI::App& app, int argc, char** argv) {
  CLI::App* current = &app;
  std::string where = "canopy";
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    const std::vector<CLI::App*> subs = subcommands(*current);
    if (subs.empty() || arg.empty() || arg[0] == '-') return;
    CLI::App* next = nullptr;
    std::string names;
    for (CLI::App* s : subs) {
      if (s->get_name() == arg) next = s;
      names += (names.empty() ? "" : ", ") + s->get_name();
    }
    if (!next) throw canopy::InputError("unknown command '" + arg + "' for '" + where + "'; the commands are: " + names);
    current = next;
    where += " " + arg;
  }
}

// Every floating-point option of every command rejects nan and inf (CLI11 parses them,
// and a range check passes nan).
void require_finite_numbers(CLI::App& app) {
  const CLI::Validator finite(
      [](std::string& text) -> std::string {
        const double v = std::strtod(text.c_str(), nullptr);
        return std::isfinite(v) ? std::string() : "value '" + text + "' is not a finite number";
      },
      "", "FINITE");
  for (CLI::Option* o : app.get_options())
    if (o->get_type_name().rfind("FLOAT", 0) == 0) o->check(finite);
  for (CLI::App* s : subcommands(app)) require_finite_numbers(*s);
}

}  // namespace

int main(int argc, char** argv) {
  canopy::install_interrupt_handlers();
  // With two cores, the software rasteriser's own threads (one per core by default) compete
  // with the mission's second thread: a frame drawn on the calling thread ends the default
  // mission sooner, with the same images (docs/architecture.md). A value the user set is kept.
  // Set before any thread or GL context exists.
  if (std::thread::hardware_concurrency() <= 2) ::setenv("LP_NUM_THREADS", "0", /*overwrite=*/0);
  CLI::App app{"canopy: simulator and planner for active semantic mapping in greenhouses"};
  app.require_subcommand(1);
  app.set_help_all_flag("--help-all", "Show help for every subcommand");
  app.set_version_flag("--version", "canopy " CANOPY_VERSION);
  // Flag errors read like every other input error: one line, exit code 2.
  app.failure_message(
      [](const CLI::App*, const CLI::Error& e) { return "canopy: error: " + std::string(e.what()) + "\n"; });
  spdlog::set_pattern("[%H:%M:%S.%e] %^%l%$ %v");
  spdlog::set_default_logger(spdlog::stderr_color_mt("canopy"));
  canopy::set_warning_handler([](const std::string& line) { spdlog::warn("{}", line); });

  canopy::cli::add_world_command(app);
  canopy::cli::add_render_command(app);
  canopy::cli::add_import_plant_command(app);
  canopy::cli::add_run_command(app);
  canopy::cli::add_mission_command(app);
  canopy::cli::add_map_command(app);
  canopy::cli::add_export_mcap_command(app);
  canopy::cli::add_ablate_command(app);
  canopy::cli::add_experiment_command(app);
  canopy::cli::add_report_command(app);
  canopy::cli::add_reach_command(app);
  canopy::cli::add_visibility_command(app);
  canopy::cli::add_nbv_command(app);
  canopy::cli::add_settings_command(app);
  CLI::App* bench = app.add_subcommand("bench", "Benchmarks that print timings (not tests)");
  bench->require_subcommand(1);
  canopy::cli::add_bench_render(*bench);
  canopy::cli::add_bench_map(*bench);
  canopy::cli::add_bench_gain(*bench);
  canopy::cli::add_bench_motion(*bench);
  canopy::cli::add_bench_mission(*bench);

  require_finite_numbers(app);
  require_valid_seeds(app);

  try {
    check_command_names(app, argc, argv);
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    const int code = app.exit(e);
    return code == 0 ? 0 : 2;
  } catch (const canopy::Interrupted& e) {
    std::fprintf(stderr, "canopy: %s\n", one_line(e.what()).c_str());
    return canopy::interrupt_exit_code();
  } catch (const canopy::InputError& e) {
    std::fprintf(stderr, "canopy: error: %s\n", one_line(e.what()).c_str());
    return 2;
  } catch (const canopy::IoError& e) {
    std::fprintf(stderr, "canopy: error: %s\n", one_line(e.what()).c_str());
    return 2;
  } catch (const std::filesystem::filesystem_error& e) {  // the system refused a file operation
    std::fprintf(stderr, "canopy: error: %s\n", one_line(canopy::describe_filesystem_error(e)).c_str());
    return 2;
  } catch (const std::bad_alloc&) {
    std::fprintf(stderr, "canopy: error: out of memory\n");
    return 1;
  } catch (const canopy::InternalError& e) {
    std::fprintf(stderr, "canopy: internal error: %s\n", e.what());
    return 1;
  } catch (const std::exception& e) {  // a failed run: not bad input, not a bug
    std::fprintf(stderr, "canopy: error: %s\n", e.what());
    return 1;
  }
  return 0;
}
