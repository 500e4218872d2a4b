#include "canopy/jobs/bench_mission.h"

#include <sys/resource.h>

#include <cstdio>
#include <sstream>

#include "canopy/common/error.h"
#include "canopy/jobs/world_job.h"
#include "canopy/mission/mission.h"

namespace canopy::jobs {

namespace {

double peak_rss_mb() {
  rusage u{};
  getrusage(RUSAGE_SELF, &u);
  return double(u.ru_maxrss) / 1024.0;
}

// The kernel's current resident set (VmRSS of /proc/self/status), 0 where it cannot be read.
double rss_now_mb() {
  std::FILE* f = std::fopen("/proc/self/status", "r");
  if (!f) return 0.0;
  char line[256];
  double kb = 0.0;
  while (std::fgets(line, sizeof line, f))
    if (std::sscanf(line, "VmRSS: %lf kB", &kb) == 1) break;
  std::fclose(f);
  return kb / 1024.0;
}

}  // namespace

std::vector<RowSize> parse_row_sizes(const std::string& text, const std::string& where) {
  std::vector<RowSize> out;
  std::stringstream in(text);
  std::string item;
  while (std::getline(in, item, ',')) {
    RowSize r;
    char colon = 0;
    std::istringstream one(item);
    if (!(one >> r.plants_per_row >> colon >> r.stops) || colon != ':' || !one.eof() || r.plants_per_row < 1 ||
        r.plants_per_row > 1000 || r.stops < 1 || r.stops > 1000)
      throw InputError(where + ": '" + item + "' is not PLANTS_PER_ROW:STOPS with both in 1..1000");
    out.push_back(r);
  }
  if (out.empty() || out.size() > 8) throw InputError(where + ": give 1 to 8 sizes, e.g. 4:5,16:20");
  return out;
}

std::vector<BenchMissionLine> bench_mission(const BenchMissionParams& params) {
  const world::WorldSpec base = load_world_spec(params.world_file);
  const auto say = [&](const std::string& line) {
    if (params.progress) params.progress(line);
  };
  std::vector<BenchMissionLine> lines;
  for (const RowSize& r : params.rows) {
    world::WorldSpec spec = base;
    spec.rows.plants_per_row = r.plants_per_row;
    settings::Settings s = params.settings;
    s.set("mission.stops.count", std::to_string(r.stops), "--rows");
    // Stops given by position (mission.stops.positions_m, e.g. a few at each end of a
    // compartment's row) are kept for a row size with as many stops; else evenly spaced.
    const std::size_t given = s.mission.stops.positions_m.size();
    if (given > 0 && given != static_cast<std::size_t>(r.stops))
      throw InputError("--rows " + std::to_string(r.plants_per_row) + ":" + std::to_string(r.stops) + ": the settings give " +
                       std::to_string(given) + " stop positions (mission.stops.positions_m); give as many stops");
    BenchMissionLine line;
    line.size = r;
    const Stopwatch build;
    const world::World world = build_world(spec);
    line.build_s = build.seconds();
    line.plants = static_cast<int>(world.plants.size());
    line.world_rss_mb = rss_now_mb();
    say("bench mission: " + std::to_string(line.plants) + " plants (" + std::to_string(r.plants_per_row) +
        " per row), " + std::to_string(r.stops) + " stops, method " + s.method.name);
    // Progress from the mission's own lines: an on_view callback would make every move wait
    // for the last scan (no overlapped moves), unlike `canopy mission`.
    mission::MissionCallbacks cb;
    cb.progress = [&](const std::string& m) {
      int k = 0, n = 0;
      if (m.find(": driving") != std::string::npos && std::sscanf(m.c_str(), "stop %d/%d", &k, &n) == 2 && k % 10 == 1)
        say("  stop " + std::to_string(k) + "/" + std::to_string(n));
      if (m.find("the base did not reach") != std::string::npos) say("  " + m);
    };
    mission::Mission mission(world, s, params.seed, cb);
    line.setup_rss_mb = rss_now_mb();
    const records::MissionResult res = mission.run();
    line.held = mission.memory();
    line.views = res.successful_views();
    line.stops_not_reached = res.stops_not_reached();
    line.wall_s = res.wall_time_s;
    line.sim_s = res.sim_time_s;
    line.times = res.times;
    line.rss_mb = peak_rss_mb();
    lines.push_back(line);
  }
  return lines;
}

}  // namespace canopy::jobs
