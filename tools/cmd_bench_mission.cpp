// canopy bench mission: a mission's wall time per view as the greenhouse row grows
// (jobs::bench_mission), or the same mission by two builds (jobs::bench_compare). This file
// translates the flags and prints.

#include <spdlog/spdlog.h>

#include <algorithm>
#include <cstdio>
#include <filesystem>

#include "canopy/jobs/bench_compare.h"
#include "canopy/jobs/bench_mission.h"
#include "cli_util.h"
#include "commands.h"

namespace canopy::cli {

void add_bench_mission(CLI::App& bench) {
  struct Options {
    std::string world = default_world_path();
    std::string config = settings::default_settings_path();
    std::string rows = "4:5,16:20";
    std::string method = "ours";
    unsigned seed = 1;
    std::string against, save;
    int repeats = 3;
    std::vector<std::string> sets;
  };
  auto opt = std::make_shared<Options>();
  CLI::App* sub = bench.add_subcommand(
      "mission", "Wall time per view of the same mission on longer rows: per-phase split and the ratio to the first");
  sub->add_option("--world", opt->world, "World file (YAML); its rows.plants_per_row is replaced")->capture_default_str();
  sub->add_option("--config", opt->config, "Settings bundle (YAML)")->capture_default_str();
  sub->add_option("--rows", opt->rows, "Row sizes to run, PLANTS_PER_ROW:STOPS,... (the first is the reference)")
      ->capture_default_str();
  sub->add_option("--method", opt->method, "View planner")->capture_default_str();
  sub->add_option("--seed", opt->seed, "Mission seed")->capture_default_str();
  sub->add_option("--against", opt->against,
                  "Another canopy (e.g. a build of main) or a measurement saved by --save: runs `canopy mission` "
                  "with both, interleaved, and prints the ratio of the median wall times (no --rows)");
  sub->add_option("--repeats", opt->repeats, "Missions per build with --against / --save")
      ->capture_default_str()
      ->check(CLI::Range(1, 100));
  sub->add_option("--save", opt->save, "Save this build's missions (--against's saved form) to this JSON file");
  sub->add_option("--set", opt->sets,
                  "KEY=VALUE given to the missions (to both builds' with --against / --save); with --rows, stops "
                  "given by mission.stops.positions_m are kept for a row size with as many");
  sub->callback([opt] {
    if (!opt->against.empty() || !opt->save.empty()) {
      jobs::BenchCompareParams p;
      p.self = std::filesystem::read_symlink("/proc/self/exe").string();
      p.against = opt->against;
      p.world_file = opt->world;
      p.method = opt->method;
      p.seed = opt->seed;
      p.repeats = opt->repeats;
      p.sets = opt->sets;
      p.save = opt->save;
      const jobs::BenchCompareResult r = jobs::bench_compare(p);
      auto list = [](const std::vector<double>& v) {
        std::string s;
        char buf[32];
        for (const double x : v) {
          std::snprintf(buf, sizeof buf, "%s%.2f", s.empty() ? "" : " ", x);
          s += buf;
        }
        return s;
      };
      auto loads = [&](const jobs::BenchSide& side) {
        double lo = 1e9, hi = 0;
        for (const double l : side.load) lo = std::min(lo, l), hi = std::max(hi, l);
        return side.load.empty() ? std::string("-") : list({lo}) + "-" + list({hi});
      };
      std::printf("bench mission: method %s, seed %u, world %s, %d run(s) per build%s\n", opt->method.c_str(), opt->seed,
                  opt->world.c_str(), opt->repeats, r.saved_old || opt->against.empty() ? "" : ", interleaved");
      std::printf("%-5s %9s %8s %7s %11s  %s\n", "build", "median s", "views", "sim s", "load (1min)", "wall s of each run");
      const auto line = [&](const char* name, const jobs::BenchSide& s) {
        std::printf("%-5s %9.2f %8d %7.1f %11s  %s   %s\n", name, s.median_s(), s.views, s.sim_s, loads(s).c_str(),
                    list(s.wall_s).c_str(), s.binary.c_str());
      };
      if (!opt->against.empty()) line(r.saved_old ? "saved" : "old", r.old_side);
      line("new", r.new_side);
      if (!opt->against.empty()) {
        std::printf("ratio new/old: %.3f (%.2fx as fast)%s\n", r.ratio(), r.ratio() > 0 ? 1.0 / r.ratio() : 0.0,
                    r.saved_old ? "; old side saved earlier, not interleaved" : "");
        std::printf("views.csv %s, map.csm %s\n", r.same_views() ? "identical" : "DIFFERENT",
                    r.same_map() ? "identical" : "DIFFERENT");
      }
      if (!opt->save.empty()) std::printf("saved: %s\n", opt->save.c_str());
      return;
    }
    jobs::BenchMissionParams p;
    p.world_file = opt->world;
    p.rows = jobs::parse_row_sizes(opt->rows, "--rows");
    p.settings = load_settings(opt->config);
    p.settings.set("method.name", opt->method, "--method");
    apply_set_options(p.settings, opt->sets);
    p.seed = opt->seed;
    p.progress = [](const std::string& line) { spdlog::info("{}", line); };
    const std::vector<jobs::BenchMissionLine> lines = jobs::bench_mission(p);
    std::printf("bench mission: method %s, seed %u (wall times on this machine; ms per successful view)\n",
                opt->method.c_str(), opt->seed);
    std::printf("%7s %6s %6s %9s %9s %8s %7s %10s %10s %10s %10s %10s %8s\n", "plants", "stops", "views", "world s",
                "wall s", "ms/view", "ratio", "evaluation", "rendering", "mapping", "clustering", "control", "peak MB");
    for (const jobs::BenchMissionLine& l : lines) {
      const double ratio = l.per_view_ms(l.wall_s) / lines.front().per_view_ms(lines.front().wall_s);
      std::printf("%7d %6d %6d %9.1f %9.1f %8.1f %7.2f %10.1f %10.1f %10.1f %10.1f %10.1f %8.0f\n", l.plants,
                  l.size.stops, l.views, l.build_s, l.wall_s, l.per_view_ms(l.wall_s), ratio,
                  l.per_view_ms(l.times.get("evaluation")), l.per_view_ms(l.times.get("rendering")),
                  l.per_view_ms(l.times.get("mapping")), l.per_view_ms(l.times.get("clustering")),
                  l.per_view_ms(l.times.get("control")), l.rss_mb);
    }
    std::printf("(phase columns: ms per view; ratio: ms/view over the first row's; peak MB: the process's peak so far)\n");
    for (const jobs::BenchMissionLine& l : lines)
      if (l.stops_not_reached > 0)
        std::printf("warning, %d plants: %d of %d stops not reached by the base (base_failed): the line covers the "
                    "other stops only\n",
                    l.plants, l.stops_not_reached, l.size.stops);
    std::printf("memory, MB: the process's resident set with the world, with the mission set up (simulator, renderer,\n"
                "truth voxels), its peak after the mission; the mission's holders at its end\n");
    for (const jobs::BenchMissionLine& l : lines) {
      const mission::MissionMemory& m = l.held;
      const auto mb = [](std::size_t b) { return double(b) / (1024.0 * 1024.0); };
      std::printf("memory, %d plants: world %.0f, set up %.0f, peak %.0f; map %.0f, nbv index %.0f, planning env %.0f, "
                  "truth env %.0f, evaluation %.0f\n",
                  l.plants, l.world_rss_mb, l.setup_rss_mb, l.rss_mb, mb(m.map), mb(m.nbv_index), mb(m.planning_env),
                  mb(m.truth_env), mb(m.evaluation));
    }
    for (const jobs::BenchMissionLine& l : lines) {
      std::printf("phases, %d plants:", l.plants);
      for (const auto& [phase, t] : l.times.totals()) std::printf(" %s %.2f s;", phase.c_str(), t);
      std::printf("\n");
    }
  });
}

}  // namespace canopy::cli
