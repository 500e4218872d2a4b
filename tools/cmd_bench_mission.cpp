// canopy bench mission: a mission's wall time per view as the greenhouse row grows.

#include <spdlog/spdlog.h>
#include <sys/resource.h>

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <sstream>

#include "canopy/common/timer.h"
#include "canopy/jobs/bench_compare.h"
#include "canopy/mission/mission.h"
#include "cli_util.h"
#include "commands.h"

namespace canopy::cli {

namespace {

struct RowSize {
  int plants_per_row = 0;
  int stops = 0;
};

// "4:5,16:20" -> {(4, 5), (16, 20)}.
std::vector<RowSize> parse_rows(const std::string& text) {
  std::vector<RowSize> out;
  std::stringstream in(text);
  std::string item;
  while (std::getline(in, item, ',')) {
    RowSize r;
    char colon = 0;
    std::istringstream one(item);
    if (!(one >> r.plants_per_row >> colon >> r.stops) || colon != ':' || !one.eof() || r.plants_per_row < 1 ||
        r.plants_per_row > 1000 || r.stops < 1 || r.stops > 1000)
      throw InputError("--rows: '" + item + "' is not PLANTS_PER_ROW:STOPS with both in 1..1000");
    out.push_back(r);
  }
  if (out.empty() || out.size() > 8) throw InputError("--rows: give 1 to 8 sizes, e.g. 4:5,16:20");
  return out;
}

double peak_rss_mb() {
  rusage u{};
  getrusage(RUSAGE_SELF, &u);
  return double(u.ru_maxrss) / 1024.0;
}

}  // namespace

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
  sub->add_option("--set", opt->sets, "KEY=VALUE given to both builds' missions (with --against / --save)");
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
    const std::vector<RowSize> rows = parse_rows(opt->rows);
    const world::WorldSpec base = jobs::load_world_spec(opt->world);
    settings::Settings settings = load_settings(opt->config);
    settings.set("method.name", opt->method, "--method");
    struct Line {
      RowSize size;
      int plants = 0, views = 0;
      double build_s = 0, wall_s = 0, sim_s = 0, rss_mb = 0;
      PhaseTimes times;
    };
    std::vector<Line> lines;
    for (const RowSize& r : rows) {
      world::WorldSpec spec = base;
      spec.rows.plants_per_row = r.plants_per_row;
      settings::Settings s = settings;
      s.set("mission.stops.count", std::to_string(r.stops), "--rows");
      s.mission.stops.positions_m.clear();
      Line line;
      line.size = r;
      const Stopwatch build;
      const world::World world = jobs::build_world(spec);
      line.build_s = build.seconds();
      line.plants = static_cast<int>(world.plants.size());
      spdlog::info("bench mission: {} plants ({} per row), {} stops, method {}", line.plants, r.plants_per_row, r.stops,
                   opt->method);
      // Progress from the mission's own lines: an on_view callback would make every move wait
      // for the last scan (no overlapped moves), unlike `canopy mission`.
      mission::MissionCallbacks cb;
      cb.progress = [&](const std::string& m) {
        int k = 0, n = 0;
        if (m.find(": driving") != std::string::npos && std::sscanf(m.c_str(), "stop %d/%d", &k, &n) == 2 && k % 10 == 1)
          spdlog::info("  stop {}/{}", k, n);
      };
      mission::Mission mission(world, s, opt->seed, cb);
      const records::MissionResult res = mission.run();
      line.views = res.successful_views();
      line.wall_s = res.wall_time_s;
      line.sim_s = res.sim_time_s;
      line.times = res.times;
      line.rss_mb = peak_rss_mb();
      lines.push_back(line);
    }
    const auto per_view = [](const Line& l, double s) { return l.views ? s / l.views * 1000.0 : 0.0; };
    std::printf("bench mission: method %s, seed %u (wall times on this machine; ms per successful view)\n",
                opt->method.c_str(), opt->seed);
    std::printf("%7s %6s %6s %9s %9s %8s %7s %10s %10s %10s %10s %10s %8s\n", "plants", "stops", "views", "world s",
                "wall s", "ms/view", "ratio", "evaluation", "rendering", "mapping", "clustering", "control", "peak MB");
    for (const Line& l : lines) {
      const double ratio = per_view(l, l.wall_s) / per_view(lines.front(), lines.front().wall_s);
      std::printf("%7d %6d %6d %9.1f %9.1f %8.1f %7.2f %10.1f %10.1f %10.1f %10.1f %10.1f %8.0f\n", l.plants,
                  l.size.stops, l.views, l.build_s, l.wall_s, per_view(l, l.wall_s), ratio,
                  per_view(l, l.times.get("evaluation")), per_view(l, l.times.get("rendering")),
                  per_view(l, l.times.get("mapping")), per_view(l, l.times.get("clustering")),
                  per_view(l, l.times.get("control")), l.rss_mb);
    }
    std::printf("(phase columns: ms per view; ratio: ms/view over the first row's; peak MB: the process's peak so far)\n");
    for (const Line& l : lines) {
      std::printf("phases, %d plants:", l.plants);
      for (const auto& [phase, t] : l.times.totals()) std::printf(" %s %.2f s;", phase.c_str(), t);
      std::printf("\n");
    }
  });
}

}  // namespace canopy::cli
