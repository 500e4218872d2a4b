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
#include "canopy/nbv/view_planner.h"
#include "canopy/records/records.h"
#include "canopy/settings/settings.h"
#include "canopy/world/world.h"

namespace canopy::records {

/// views.csv (one row per attempted view, no wall times: byte-identical for a seed); its
/// columns are ViewRecord::visit's fields for views.csv (view_columns.h).
std::string views_csv(const MissionResult& result, const std::string& method);
/// timing.csv (wall time per attempted view and phase).
std::string timing_csv(const MissionResult& result);

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

/// summary.json: the mission's result and, with its settings and context, what the run was
/// (method, seed, P_gt, labels, the world, files). Its keys are named once, in visit().
struct MissionSummary {
  MissionResult& result;
  const settings::Settings* settings = nullptr;  ///< nullptr: the result's keys only.
  const RunContext* context = nullptr;

  template <class A>
  void visit(A& a);
};

/// summary.json body: per-stop counts, failures, final figures, time split (MissionSummary
/// without the run's settings).
nlohmann::json summary_json(const MissionResult& result);
/// summary.json: summary_json and what the run was (method, seed, P_gt, labels, the world, files).
nlohmann::json run_summary(const MissionResult& result, const settings::Settings& settings, const RunContext& context);
/// summary.json's keys with their units and meanings (docs/commands.md's table: summary_fields_markdown).
std::vector<FieldInfo> summary_fields();
/// The table of summary.json's keys as Markdown: docs/commands.md holds it.
std::string summary_fields_markdown();

/// Writes every file of a mission folder into `dir` (each atomically) and returns the
/// summary it wrote.
nlohmann::json write_run_folder(const std::string& dir, const MissionResult& result, const settings::Settings& settings,
                                const mapping::SemanticOcTree& map, const RunContext& context);

/// A mission folder read back.
struct RunFolder {
  std::string views_csv;                 ///< The file's text.
  std::vector<double> coverage, entropy; ///< After each successful view (headline rule).
  std::vector<std::string> phases;       ///< The phase of each successful view ("" when views.csv has no phase column).
  /// The curve columns (curve_column_names(), view_columns.h) present in the file, after each successful view (NaN where a field is empty).
  std::map<std::string, std::vector<double>> curves;
  nlohmann::json summary;
};

/// Reads views.csv and summary.json of a mission folder; throws InputError naming the file on
/// a missing or malformed one.
RunFolder read_run_folder(const std::string& dir);

template <class A>
void MissionSummary::visit(A& a) {
  using F = Field;
  MissionResult& r = result;
  a("complete", r.complete, F("", "false when the run was interrupted (the views so far are valid)"));
  a("end_reason", r.end_reason,
    F("", "why the run ended: `all stops done`, `interrupted`, or K of N stops not reached; \"most attempts failed\" "
          "added when fewer than half succeeded"));
  a("views_attempted", r.views.size(), F("", "views attempted"));
  a("views_successful", r.successful_views(), F("", "views that succeeded"));
  a("failures", r.failures, F("", "failed attempts by cause"));
  a("unstable_faults", r.unstable_faults, F("", "moves whose simulation diverged (restored)"));
  a.section("overlapped_moves", [&](auto& s) {
    s("started", r.overlapped_moves, F("", "moves started before the last scan was in the map"));
    s("kept", r.overlapped_kept, F("", "of them, those kept (the plan with the scan was the same)"));
  }, F("", "moves overlapped with the last scan's insertion (`mission.loop.overlap_moves`)"));
  a("zero_coverage_reason", r.zero_coverage_reason.empty() ? std::nullopt : std::optional<std::string>(r.zero_coverage_reason),
    F("", "when the final coverage is 0: why (also the command's last line); absent otherwise").if_present());
  a.list("stops", r.stops, F("", "one per base stop"));
  int refused = 0, repairs = 0, replaced = 0, replacement_attempts = 0, arm_contacts = 0, base_contacts = 0;
  int arm_drive_contacts = 0, arm_home_contacts = 0;
  int guarded = 0, exploration_rounds = 0;
  bool all_reached = !r.stops.empty();
  for (const StopRecord& s : r.stops) {
    refused += s.refused, repairs += s.start_repairs, replaced += s.scripted_replaced;
    guarded += s.guarded, exploration_rounds += s.exploration_rounds;
    replacement_attempts += s.replacement_attempts, base_contacts += s.base_truth_contacts;
    arm_drive_contacts += s.arm_drive_truth_contacts, arm_home_contacts += s.arm_home_truth_contacts;
    all_reached = all_reached && s.reached_goal;
  }
  for (const ViewRecord& v : r.views) arm_contacts += v.truth_contacts;
  a("refused", refused, F("", "scripted views refused before any move, all stops"));
  a("guarded", guarded, F("", "views offered again after failing at their stop, dropped by the mission, all stops"));
  a("exploration_rounds", exploration_rounds,
    F("", "rounds planned by mission.loop.exploration for a method with nothing to attempt, all stops"));
  a("start_repairs", repairs, F("", "attempts whose arm start was repaired, all stops"));
  a("scripted_replaced", replaced, F("", "failed scripted views replaced, all stops"));
  a("replacement_attempts", replacement_attempts, F("", "replacement views attempted, all stops"));
  a("all_stops_reached", all_reached, F("", "every stop's base goal reached"));
  a.section("contacts", [&](auto& s) {
    s("arm_truth_contact_checks", arm_contacts, F("", "executed arm states in contact with the true plants"));
    s("base_truth_contact_checks", base_contacts, F("", "base-vs-plant contacts while driving"));
    s("arm_drive_truth_contact_checks", arm_drive_contacts,
      F("", "arm-vs-plant contacts while driving (the arm as mission.stops.arm_on_drive left it)"));
    s("arm_home_truth_contact_checks", arm_home_contacts,
      F("", "executed arm states in contact with the true plants on the moves home before drives"));
  }, F("", "contacts with the true plants (counted, never planned with)"));
  const evaluation::MapMetrics& m = r.final_metrics;
  const nlohmann::json metrics = m.to_json();
  a.section("final", [&](auto& s) {
    s("metrics_rule", metrics["rule"], F("", "the headline rule (`mapping.metrics.rule`)"));
    s("fruit_coverage", m.coverage, F("", "fruit surface coverage at the end (headline rule)"));
    s("fruit_entropy", m.total_entropy, F("nats", "fruit entropy at the end (headline rule)"));
    s("fruit_points", m.points, F("", "true fruit surface points evaluated"));
    s("target_fruits", m.fruits.size(), F("", "target fruits in the world"));
    s("non_target_fruits", m.non_target_fruits, F("", "other fruits in the world"));
    s("rules", metrics["rules"], F("", "coverage and entropy under every rule"));
    s("fruits_sc50", metrics["fruits_sc50"], F("", "share of the target fruits with a coverage of 50 % or more"));
    s("fruits_sc80", metrics["fruits_sc80"], F("", "share of the target fruits with a coverage of 80 % or more"));
    s("detection", metrics["detection"], F("", "fruit detection and shape (docs/metrics.md)"));
    s("fruit_voxel_precision", metrics["fruit_voxel_precision"], F("", "the fruit class's voxel precision"));
  }, F("", "the map's figures at the end"));
  a.section("motion_cost", [&](auto& s) {
    s("arm_path_rad", r.arm_path_rad, F("rad", "joint-space path of every executed trajectory"));
    s("base_travel_m", r.base_travel_m, F("m", "base travel between stops"));
    s("simulated_time_s", r.sim_time_s, F("s", "simulated time of the run"));
    std::optional<nlohmann::json> at;
    if (settings) {
      const std::vector<double>& budgets = settings->mission.record.time_budgets_s;
      const std::vector<double> reached = coverage_at_times(r, budgets);
      at = nlohmann::json::array();
      for (std::size_t i = 0; i < budgets.size(); ++i) at->push_back({{"time_s", budgets[i]}, {"coverage", reached[i]}});
    }
    s("coverage_at_time", at,
      F("", "[{time_s, coverage}]: the coverage reached by each `mission.record.time_budgets_s`").if_present());
  }, F("", "what the views cost the robot"));
  a("simulated_time_s", r.sim_time_s, F("s", "simulated time of the run"));
  a("wall_time_s", r.wall_time_s, F("s", "wall time of the run (differs between equal runs)"));
  a("wall_time_by_phase_s", r.times.totals(), F("s", "wall time by phase (wall_phases; they overlap, see docs)"));
  if (!settings || !context) return;
  const nbv::ViewPlannerEntry* entry = nbv::find_view_planner(settings->method.name);
  a.section("method", [&](auto& s) {
    s("name", settings->method.name, F("", "the view planner (`method.name`)"));
    s("gain", settings->method.gain, F("", "its information gain (`method.gain`)"));
    s("rays", settings->method.rays, F("", "its ray set (`method.rays`)"));
    s("reads_ground_truth", entry && entry->reads_ground_truth, F("", "true for the oracles"));
  }, F("", "the method"));
  a("seed", context->seed, F("", "the run's seed"));
  a("p_gt", settings->mapping.extractor.p_gt, F("", "segmentation noise P_gt"));
  a("labels", std::string(perception::to_string(settings->mapping.extractor.source)), F("", "`color` or `truth`"));
  std::optional<nlohmann::json> world;
  if (context->world)
    world = nlohmann::json{{"file", context->world_file},
                           {"plants", context->world->plants.size()},
                           {"fruits", context->world->truth.fruits.size()},
                           {"triangles", context->world->triangle_count()},
                           {"spec", context->world->spec.to_json()}};
  a("world", world, F("", "{file, plants, fruits, triangles, spec}: the world and its resolved spec").if_present());
  a("settings_file", std::string("settings.yaml"), F("", "the settings bundle the run saved"));
  std::vector<std::string> files = {"views.csv", "timing.csv", "fruit_shapes.csv", "settings.yaml", "map.csm", "map.ply", "map.bt"};
  if (!r.candidates.empty()) files.push_back("candidates.csv");
  a("files", files, F("", "the run folder's files"));
  a("video", context->video.is_null() ? std::nullopt : std::optional<nlohmann::json>(context->video),
    F("", "{file, frames} or {file, error}; absent without a video").if_present());
  a("started_unix_ns", context->started_unix_ns,
    F("ns", "the run's start in wall-clock time (since 1970): the epoch of its recordings' stamps").if_present());
  a("recording", context->recording.is_null() ? std::nullopt : std::optional<nlohmann::json>(context->recording),
    F("", "{file, epoch_unix_ns, messages, compression}: the MCAP recorded while it ran (`--mcap`); absent "
          "without one").if_present());
}

}  // namespace canopy::records
