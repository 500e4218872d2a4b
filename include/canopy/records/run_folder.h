#pragma once
// A mission's output folder, written and read in one place (`canopy mission` writes it,
// `canopy report` reads it back from every trial of an experiment):
//   views.csv     one row per attempted view, no wall times: byte-identical for a seed;
//   timing.csv    wall time per attempted view and phase;
//   summary.json  per-stop counts and end reasons, failures, final figures, time split, the
//                 method, seed, P_gt, labels and the world;
//   settings.yaml the whole settings bundle (`--config` repeats the run);
//   map.csm, map.ply, map.bt   the final map (canopy, MeshLab, octovis).

#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "canopy/mapping/semantic_octree.h"
#include "canopy/records/records.h"
#include "canopy/settings/settings.h"
#include "canopy/world/world.h"

namespace canopy::records {

/// views.csv (one row per attempted view, no wall times: byte-identical for a seed); its
/// columns are view_columns() (view_columns.h).
std::string views_csv(const MissionResult& result, const std::string& method);
/// timing.csv (wall time per attempted view and phase).
std::string timing_csv(const MissionResult& result);
/// summary.json body: per-stop counts, failures, final figures, time split.
nlohmann::json summary_json(const MissionResult& result);

/// Coverage reached by simulated time T: that of the last attempt ending at or before T (0
/// before the first; the final coverage when the mission ended before T), for each T.
std::vector<double> coverage_at_times(const MissionResult& result, const std::vector<double>& times_s);

/// What summary.json says about the run beside its result.
struct RunContext {
  std::uint64_t seed = 1;
  std::string world_file;
  const world::World* world = nullptr;
  nlohmann::json video;  ///< {file, frames} or {file, error}; null without a video.
  /// When the run started in wall-clock time [ns since 1970] (the epoch of its recordings' stamps).
  std::optional<std::int64_t> started_unix_ns;
  nlohmann::json recording;  ///< The MCAP recorded while it ran ({file, epoch_ns, ...}); null without one.
};

/// summary.json: summary_json and what the run was (method, seed, P_gt, labels, the world, files).
nlohmann::json run_summary(const MissionResult& result, const settings::Settings& settings, const RunContext& context);

/// Writes every file of a mission folder into `dir` (each atomically) and returns the
/// summary it wrote.
nlohmann::json write_run_folder(const std::string& dir, const MissionResult& result, const settings::Settings& settings,
                                const mapping::SemanticOcTree& map, const RunContext& context);

/// A mission folder read back.
struct RunFolder {
  std::string views_csv;                 ///< The file's text.
  std::vector<double> coverage, entropy; ///< After each successful view (headline rule).
  /// The curve columns (curve_column_names(), view_columns.h) present in the file, after each successful view (NaN where a field is empty).
  std::map<std::string, std::vector<double>> curves;
  nlohmann::json summary;
};

/// Reads views.csv and summary.json of a mission folder; throws InputError naming the file on
/// a missing or malformed one.
RunFolder read_run_folder(const std::string& dir);

}  // namespace canopy::records
