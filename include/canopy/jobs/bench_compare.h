#pragma once
// Job: the same `canopy mission` run by two builds of canopy, interleaved in one session (old,
// new, new, old, ...), so that both see the same machine load; the ratio of their median mission
// wall times is the speed-up. `canopy bench mission --against OLD` prints it. The old side may
// also be a saved measurement (--save of an earlier run), then only this build runs.
//
// The runs are child processes started without a shell (run_process); each writes a run folder
// in a private temporary folder, whose summary.json gives the mission wall time and whose
// views.csv and map.csm are compared byte for byte between the two builds.

#include <string>
#include <vector>

#include <nlohmann/json.hpp>

namespace canopy::jobs {

/// What bench_compare runs.
struct BenchCompareParams {
  std::string self;                 ///< This build's canopy (the new side).
  std::string against;              ///< The old canopy, or a .json saved by `save`.
  std::string world_file = "worlds/default.yaml";
  std::string method = "ours";
  unsigned seed = 1;
  int repeats = 3;                  ///< Missions per side.
  std::vector<std::string> sets;    ///< --set KEY=VALUE given to both sides.
  std::string save;                 ///< When not empty: this build's measurement, as JSON.
};

/// One side's runs.
struct BenchSide {
  std::string binary;               ///< The program run ("" for a saved measurement).
  std::vector<double> wall_s;       ///< Mission wall time of each run (summary.json wall_time_s).
  std::vector<double> load;         ///< The 1-minute load average before each run.
  double sim_s = 0.0;               ///< Simulated time of the mission.
  int views = 0;                    ///< Successful views.
  std::string views_digest, map_digest;  ///< FNV-1a digests of the first run's views.csv and map.csm.
  double median_s() const;
  nlohmann::json to_json() const;
  static BenchSide from_json(const nlohmann::json& j, const std::string& what);
};

/// The two sides and their ratio.
struct BenchCompareResult {
  BenchSide old_side, new_side;
  bool saved_old = false;           ///< The old side came from a saved measurement.
  double ratio() const;             ///< New median over old median (below 1: the new build is faster).
  bool same_views() const { return old_side.views_digest == new_side.views_digest; }
  bool same_map() const { return old_side.map_digest == new_side.map_digest; }
};

/// Runs the missions (InputError for a bad program or saved file; IoError when a run fails).
BenchCompareResult bench_compare(const BenchCompareParams& params);

}  // namespace canopy::jobs
