#pragma once
// Job: a mission's wall time per view as the greenhouse row grows (`canopy bench mission
// --rows`): the same mission on worlds whose rows hold more plants, with more stops, each line
// with its per-phase split and the process's peak memory. (Two builds compared on one mission
// are bench_compare.h.)

#include <functional>
#include <string>
#include <vector>

#include "canopy/common/timer.h"
#include "canopy/mission/mission.h"
#include "canopy/settings/settings.h"

namespace canopy::jobs {

/// One row size: plants per row and the mission's stops.
struct RowSize {
  int plants_per_row = 0;
  int stops = 0;
};

/// "4:5,16:20" -> {(4, 5), (16, 20)}: 1 to 8 sizes, each number in 1..1000; InputError naming
/// `where` otherwise.
std::vector<RowSize> parse_row_sizes(const std::string& text, const std::string& where);

/// What bench_mission runs.
struct BenchMissionParams {
  std::string world_file = "worlds/default.yaml";  ///< Its rows.plants_per_row is replaced.
  settings::Settings settings;                      ///< Its mission.stops.count is replaced.
  std::vector<RowSize> rows;                        ///< The first is the reference.
  unsigned seed = 1;
  /// Progress lines (the row being run, every tenth stop); may be null.
  std::function<void(const std::string&)> progress;
};

/// One row size's mission.
struct BenchMissionLine {
  RowSize size;
  int plants = 0, views = 0;   ///< Plants of the world; successful views.
  int stops_not_reached = 0;   ///< Stops the base did not reach (base_failed): the figures cover the others.
  double build_s = 0.0;        ///< Generating the world.
  double wall_s = 0.0, sim_s = 0.0;
  double rss_mb = 0.0;         ///< The process's peak resident memory after it.
  /// The process's resident memory (the kernel's VmRSS) with the world generated, and with the
  /// mission set up too (its simulator, renderer and truth voxels), before it runs.
  double world_rss_mb = 0.0, setup_rss_mb = 0.0;
  mission::MissionMemory held;  ///< The mission's largest holders at its end.
  PhaseTimes times;
  /// `seconds` per successful view, in ms (0 without views).
  double per_view_ms(double seconds) const { return views ? seconds / views * 1000.0 : 0.0; }
};

/// Runs the mission once per row size, in order.
std::vector<BenchMissionLine> bench_mission(const BenchMissionParams& params);

}  // namespace canopy::jobs
